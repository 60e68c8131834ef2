#pragma once

#include <cstddef>
#include <string>

#include "hullmap/collision/path_check.hpp"

namespace hullmap::pipeline {

/// One segment's check as the JSON line `hullmap check --json` prints (no trailing newline):
/// `{"index":i,"collides":b,"obstacle":id|null[,"part":k],"surface":name|null,"t":t|null,"clearance":c}`;
/// obstacle is null when clear, in octree mode or when a surface is hit, part only when the obstacle
/// has convex parts, surface the name of the surface hit ("floor", "ceiling") or null, t null when
/// clear. The CLI and the ROS node's ~path_check print it, so both read the same.
std::string segmentCheckJsonLine(std::size_t index, const collision::SegmentCheck& check);

}  // namespace hullmap::pipeline
