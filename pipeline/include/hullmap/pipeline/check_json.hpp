#pragma once

#include <cstddef>
#include <string>

#include "hullmap/collision/path_check.hpp"

namespace hullmap::pipeline {

/// One segment's check as the JSON line `hullmap check --json` prints (no trailing newline):
/// `{"index":i,"collides":b,"obstacle":id|null[,"part":k],"t":t|null,"clearance":c}`; obstacle is
/// null when clear (or in octree mode), part only when the obstacle has convex parts, t null when
/// clear. The CLI and the ROS node's ~path_check print it, so both read the same.
std::string segmentCheckJsonLine(std::size_t index, const collision::SegmentCheck& check);

}  // namespace hullmap::pipeline
