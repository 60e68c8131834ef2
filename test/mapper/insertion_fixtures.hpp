#pragma once
// Helpers shared by mapper/insertion.cpp, mapper/heavy/insertion.cpp.

#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <tuple>

#include "hullmap/mapper/detail/octree_keys.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "octree_oracle.hpp"
#include "test_support.hpp"

namespace hullmap::mapper {

namespace {
using namespace hullmap::io;
using namespace hullmap::sim;
using test::sameTree;

inline void expectSameAsOctomap(const Points& points, const Point& origin, double resolution, double max_range,
                                int repeats) {
  octomap::OcTree expected(resolution);
  octomap::OcTree actual(resolution);
  const octomap::Pointcloud cloud = test::toCloud(points);
  for (int r = 0; r < repeats; ++r) {
    expected.insertPointCloud(cloud, test::toPoint3d(origin), max_range);
    insertScan(actual, points, origin, max_range);
    ASSERT_TRUE(sameTree(expected, actual))
        << "resolution " << resolution << ", max_range " << max_range << ", insertion " << r + 1;
  }
}

}  // namespace
}  // namespace hullmap::mapper
