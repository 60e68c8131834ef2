#pragma once

#include <string>
#include <vector>

namespace hullmap::cli {

/// Warnings for a path check against the hulls in `obstacles_json` (holding `obstacles` of them):
/// clustering::hullCheckWarnings, in the CLI's words, over the numbers of the report.json beside it (when there is one;
/// without it only "no obstacle" can be told).
std::vector<std::string> hullCheckWarnings(const std::string& obstacles_json, std::size_t obstacles);

/// Throws hullmap::Error when `path`, given as the input of a hull check, is an octree (.bt/.ot
/// name or OctoMap header): "<path>: an octree, not obstacles; check it with --against octree, or
/// give a `hullmap build` directory or its obstacles.json".
void refuseOctreeAsHulls(const std::string& path);

}  // namespace hullmap::cli
