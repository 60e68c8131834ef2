#pragma once
// Helpers shared by collision/checker.cpp, collision/heavy/checker.cpp.

#include <fcl/geometry/shape/sphere.h>
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include "collision_oracle.hpp"
#include "hullmap/collision/fcl_obstacles.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::collision {

namespace {
using test::V3;

struct Scene {
  std::vector<hulls::Obstacle> obstacles;
  test::VoxelBlobs voxels;
};

inline Scene randomScene(std::uint32_t seed, int clusters, double size) {
  std::mt19937 rng(seed);
  Scene s;
  s.voxels = test::randomBlobs(rng, clusters, 150, size, 30);
  s.obstacles = hulls::buildObstacles(s.voxels.centers, s.voxels.weights, s.voxels.labels, size);
  return s;
}

inline Segment randomSegment(std::mt19937& rng, double extent, double max_length) {
  std::uniform_real_distribution<double> u(-1, 1);
  const V3 a(u(rng) * extent, u(rng) * extent, (u(rng) + 1) * 0.6 * extent);
  const V3 d(u(rng), u(rng), u(rng));
  return {a, a + d * max_length * (u(rng) + 1) / 2};
}

}  // namespace
}  // namespace hullmap::collision
