#include "hullmap/pipeline/path_checker.hpp"

namespace hullmap::pipeline {

collision::HullChecker pathChecker(const MapObstacles& map) {
  return collision::HullChecker(map.obstacles, map.surfaces);
}

}  // namespace hullmap::pipeline
