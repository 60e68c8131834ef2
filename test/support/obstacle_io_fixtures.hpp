#pragma once
// Helpers shared by collision/obstacle_io.cpp, e2e/check.cpp.

#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "test_support.hpp"

namespace hullmap::pipeline {
using hullmap::test::writeText;

namespace {
using V3 = Eigen::Vector3d;

/// Two boxes of voxels: obstacle 0 at x in [1, 2], obstacle 3 at x in [4, 5]; y, z in [0, 1].
inline std::vector<hulls::Obstacle> twoBoxes(std::vector<V3>* voxels = nullptr) {
  std::vector<V3> centers;
  std::vector<std::int32_t> labels;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) {
        centers.push_back(V3(1.05 + 0.1 * i, 0.05 + 0.1 * j, 0.05 + 0.1 * k));
        labels.push_back(0);
        centers.push_back(V3(4.05 + 0.1 * i, 0.05 + 0.1 * j, 0.05 + 0.1 * k));
        labels.push_back(3);
      }
  if (voxels) *voxels = centers;
  return hulls::buildObstacles(centers, {}, labels, 0.1);
}

}  // namespace
}  // namespace hullmap::pipeline
