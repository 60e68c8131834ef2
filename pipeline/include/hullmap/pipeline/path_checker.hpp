#pragma once

#include "hullmap/collision/path_check.hpp"
#include "hullmap/pipeline/map_obstacles.hpp"

namespace hullmap::pipeline {

/// The hull checker a build's paths are checked with: its obstacles (their convex parts) and its
/// surfaces (floor, ceiling), as readMapObstacles gives them. What `hullmap check` (hull mode), `plot
/// --path` and `view --path` all call, so that the three answer alike for the same path. Coordinates in
/// the build's output frame, map units. Throws hullmap::Error as collision::HullChecker's constructor.
collision::HullChecker pathChecker(const MapObstacles& map);

}  // namespace hullmap::pipeline
