#pragma once

#include <string>

#include "hullmap/planning/roadmap.hpp"

namespace hullmap::planning {

/// Reads a roadmap.json ("hullmap-roadmap/1", written by writeRoadmapJson) back; roadmapJson of
/// the result is the file's text again. Throws hullmap::Error naming `path` and what is wrong
/// (cannot open, not JSON, another format, a missing or mistyped field, an edge naming a node that
/// does not exist).
Roadmap readRoadmapJson(const std::string& path);

}  // namespace hullmap::planning
