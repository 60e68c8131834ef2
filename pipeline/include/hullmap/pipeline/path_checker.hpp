#pragma once

#include <filesystem>
#include <vector>

#include "hullmap/clustering/obstacles.hpp"
#include "hullmap/collision/path_check.hpp"

namespace hullmap::pipeline {

/// The hull checker a build's paths are checked with: what `hullmap check` (hull mode), `plot --path`
/// and `view --path` all call, so that the three answer alike for the same path. `obstacles` are
/// those read from `obstacles_json` (readObstacles); what else the check takes from the build is
/// read from beside it. Coordinates in the build's output frame, map units. Throws hullmap::Error
/// as collision::HullChecker's constructor does.
collision::HullChecker pathChecker(const std::filesystem::path& obstacles_json,
                                   const std::vector<clustering::Obstacle>& obstacles);

}  // namespace hullmap::pipeline
