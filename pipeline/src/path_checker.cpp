#include "hullmap/pipeline/path_checker.hpp"

namespace hullmap::pipeline {

collision::HullChecker pathChecker(const std::filesystem::path& /*obstacles_json*/,
                                   const std::vector<clustering::Obstacle>& obstacles) {
  return collision::HullChecker(obstacles);
}

}  // namespace hullmap::pipeline
