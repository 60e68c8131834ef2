#pragma once
// Helpers that test/sim's evaluate and height-field tests share.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::test {

/// An obstacle (id `id`) of the 0.1 m voxels filling [lo, hi) exactly.
inline hulls::Obstacle filledObstacle(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int id) {
  std::vector<Eigen::Vector3d> centers;
  for (double x = lo.x() + 0.05; x < hi.x(); x += 0.1)
    for (double y = lo.y() + 0.05; y < hi.y(); y += 0.1)
      for (double z = lo.z() + 0.05; z < hi.z(); z += 0.1) centers.emplace_back(x, y, z);
  auto obstacles = hulls::buildObstacles(centers, {}, std::vector<std::int32_t>(centers.size(), 0), 0.1);
  obstacles.at(0).id = id;
  return obstacles[0];
}

}  // namespace hullmap::test
