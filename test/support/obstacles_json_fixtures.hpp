#pragma once
// Helpers shared by pipeline/obstacles_json.cpp, e2e/obstacles_json.cpp.

#include <gtest/gtest.h>
#include <fstream>
#include <sstream>

#include "hullmap/core/error.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/obstacle_io.hpp"
#include "test_support.hpp"

namespace hullmap::pipeline {

namespace {
using V3 = Eigen::Vector3d;

/// An L (two parts) and a box (one part), 5 cm voxels.
inline std::vector<hulls::Obstacle> lAndBox() {
  std::vector<V3> centers;
  std::vector<std::int32_t> labels;
  const auto add = [&](int i0, int i1, int j0, int j1, int k1, std::int32_t label) {
    for (int i = i0; i < i1; ++i)
      for (int j = j0; j < j1; ++j)
        for (int k = 0; k < k1; ++k) {
          centers.push_back(V3(i + 0.5, j + 0.5, k + 0.5) * 0.05);
          labels.push_back(label);
        }
  };
  add(0, 30, 0, 4, 10, 0);
  add(0, 4, 4, 20, 10, 0);
  add(50, 60, 0, 5, 5, 1);
  auto obstacles = hulls::buildObstacles(centers, {}, labels, 0.05);
  hulls::addConvexParts(obstacles, centers, {}, labels, 0.05, {});
  return obstacles;
}

}  // namespace
}  // namespace hullmap::pipeline
