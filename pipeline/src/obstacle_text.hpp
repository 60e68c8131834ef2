#pragma once
// Private to hullmap_pipeline: obstacles.json's obstacles written straight to text, byte for byte
// as nlohmann's dump(1) writes obstacleJson (obstacle_io.cpp).

#include <string>

#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::pipeline {

/// obstacleJson(o).dump(1) at `depth` (what the document's list of obstacles holds), appended to `out`.
void dumpObstacleText(std::string& out, const hulls::Obstacle& o, int depth);

}  // namespace hullmap::pipeline
