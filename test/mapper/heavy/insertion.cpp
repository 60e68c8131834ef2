#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <tuple>

#include <gtest/gtest.h>

#include "hullmap/mapper/detail/octree_keys.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "insertion_fixtures.hpp"
#include "octree_oracle.hpp"
#include "test_support.hpp"

namespace hullmap::mapper {
namespace {

TEST(MapperInsertion, RealScanSameTreeAsInsertPointCloud) {
  HULLMAP_REQUIRE_REAL_DATA(path, "octomap_scan.dat");
  const Points scan = test::readXyz(path);
  ASSERT_EQ(scan.size(), 88206u);
  for (double resolution : {0.05, 0.1, 0.2}) {
    expectSameAsOctomap(scan, Point::Zero(), resolution, -1.0, 1);
  }
  // Repeated insertion drives leaves to the clamping bounds, where octomap aborts early and prunes:
  // hits clamp after 3 insertions, misses after 5; by the 7th, clamped free space is pruned into
  // leaves far above the voxels, under which every free update aborts.
  expectSameAsOctomap(scan, Point::Zero(), 0.2, -1.0, 7);
  expectSameAsOctomap(scan, Point::Zero(), 0.1, 3.0, 3);
}

TEST(MapperInsertion, GeneratedScansSameTreeAsInsertPointCloud) {
  SceneParams params;
  params.points = 30000;
  params.orbslam_frame = false;
  params.gross_outliers = 0;
  const Scene scene = generateScene(params);
  for (double resolution : {0.05, 0.13, 0.25}) {
    for (double max_range : {-1.0, 2.5}) {
      octomap::OcTree expected(resolution);
      octomap::OcTree actual(resolution);
      // Several scans from different keyframes into one tree.
      for (std::size_t k = 0; k < scene.keyframes.size(); k += 15) {
        const Point origin = scene.keyframes[k].position;
        expected.insertPointCloud(test::toCloud(scene.points), test::toPoint3d(origin), max_range);
        insertScan(actual, scene.points, origin, max_range);
        ASSERT_TRUE(sameTree(expected, actual))
            << "resolution " << resolution << " max_range " << max_range << " keyframe " << k;
      }
    }
  }
}

TEST(MapperInsertion, ClampedFreeSpaceAbortsAsOctomap) {
  // 20,000 rays to a 4 m sphere cover every 0.1 m voxel of the 1.6 m cube (a node at depth 12)
  // around the sensor: repeated, its free space clamps and is pruned into one leaf, under which
  // all later free updates abort, and octomap leaves that leaf alone.
  const Point origin(0.8, 0.8, 0.8);
  Points points;
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < 20000; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / 20000.0, r = std::sqrt(1.0 - z * z);
    points.push_back(origin + 4.0 * Point(r * std::cos(golden * i), r * std::sin(golden * i), z));
  }
  expectSameAsOctomap(points, origin, 0.1, -1.0, 7);
}

TEST(MapperInsertion, RaysBeyondTheBrickGridAsOctomap) {
  // Few long rays spread over a box too large for a grid of bricks (more than 4 KiB of grid a
  // point, or 2^22 bricks): the walked keys go through the bricks' hash, which grows as it fills.
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  for (const auto& [count, radius, resolution] :
       {std::tuple<int, double, double>{32, 20.0, 0.01}, std::tuple<int, double, double>{200, 40.0, 0.05}}) {
    Points points;
    for (int i = 0; i < count; ++i) {
      const double z = 1.0 - 2.0 * (i + 0.5) / count, r = std::sqrt(1.0 - z * z);
      points.push_back(radius * Point(r * std::cos(golden * i), r * std::sin(golden * i), z));
    }
    expectSameAsOctomap(points, Point(0.3, -0.2, 0.1), resolution, -1.0, 2);
    expectSameAsOctomap(points, Point(0.3, -0.2, 0.1), resolution, 0.5 * radius, 1);
  }
}

TEST(MapperInsertion, ExactTiesResolvedAsOctomap) {
  // Binary fractions at power-of-two resolutions: rays along diagonals cross voxel borders on
  // several axes at exactly the same t, and ends on borders make a t equal the ray's length; both
  // are decided by octomap's strict comparisons, which insertScan must repeat. The ends lie on a
  // cube's surface, so the voxels inside are free space, not endpoints.
  Points points;
  for (int i = -8; i <= 8; ++i) {
    for (int j = -8; j <= 8; ++j) {
      for (int k = -8; k <= 8; ++k) {
        if (std::max({std::abs(i), std::abs(j), std::abs(k)}) == 8) points.push_back(0.5 * Point(i, j, k));
      }
    }
  }
  for (const Point& origin : {Point(0.0, 0.0, 0.0), Point(0.125, 0.125, 0.125), Point(0.25, -0.375, 0.5)}) {
    for (double resolution : {0.25, 0.125}) {
      expectSameAsOctomap(points, origin, resolution, -1.0, 1);
      expectSameAsOctomap(points, origin, resolution, 3.0, 1);
    }
  }
}

}  // namespace
}  // namespace hullmap::mapper
