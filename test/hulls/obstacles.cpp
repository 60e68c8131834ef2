// Obstacles: the hull of a cluster contains every voxel completely and is no bigger than the hull
// of the voxels' corners; footprints and volumes against direct computations.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <tuple>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "obstacles_fixtures.hpp"
#include "test_support.hpp"

namespace hullmap::hulls {
namespace {

/// Octomap-like lattice: centres at (k + 0.5) * size.
V3 center(int i, int j, int k, double size) { return V3(i + 0.5, j + 0.5, k + 0.5) * size; }

TEST(Obstacles, SingleVoxelIsItsCube) {
  Voxels v;
  add(v, center(3, -2, 7, 0.05), 0, 4);
  const auto obstacles = buildObstacles(v.centers, v.weights, v.labels, 0.05);
  ASSERT_EQ(obstacles.size(), 1u);
  expectWraps(obstacles[0], v, 0.05);
  EXPECT_EQ(obstacles[0].hull.vertices.size(), 8u);
  EXPECT_EQ(obstacles[0].hull.triangles.size(), 12u);
  EXPECT_NEAR(obstacles[0].volume, 0.05 * 0.05 * 0.05, 1e-15);
  EXPECT_TRUE(obstacles[0].centroid.isApprox(v.centers[0], 1e-12));
  EXPECT_EQ(obstacles[0].footprint.polygon.size(), 4u);
}

TEST(Obstacles, SingleRowAndFlatWallAreNotDegenerate) {
  Voxels v;
  for (int i = 0; i < 20; ++i) add(v, center(i, 0, 0, 0.1), 0);  // a row along x
  for (int i = 0; i < 15; ++i)
    for (int k = 0; k < 10; ++k) add(v, center(40 + i, 40 + i, k, 0.1), 1);  // a staircase wall, 1 voxel thick
  for (int j = 0; j < 12; ++j)
    for (int k = 0; k < 8; ++k) add(v, center(-30, j, k, 0.1), 2);  // a flat wall in the yz plane
  const auto obstacles = buildObstacles(v.centers, v.weights, v.labels, 0.1);
  ASSERT_EQ(obstacles.size(), 3u);
  for (const auto& o : obstacles) expectWraps(o, v, 0.1);
  EXPECT_NEAR(obstacles[0].volume, 20 * 0.001, 1e-12);  // the row's hull is its box
  EXPECT_NEAR(obstacles[2].volume, 96 * 0.001, 1e-12);
  EXPECT_TRUE(obstacles[0].centroid.isApprox(V3(1.0, 0.05, 0.05), 1e-12));
}

TEST(Obstacles, RandomBlobsContainEveryVoxelAndNoiseIsNoObstacle) {
  std::mt19937 rng(7);
  Voxels v;
  const double size = 0.05;
  for (int label = 0; label < 12; ++label) {
    std::set<std::array<int, 3>> cells;
    std::array<int, 3> at{int(rng() % 200) - 100, int(rng() % 200) - 100, int(rng() % 40)};
    const int n = 1 + int(rng() % 400);
    while (int(cells.size()) < n) {
      cells.insert(at);
      at[rng() % 3] += (rng() % 2) ? 1 : -1;
    }
    for (const auto& c : cells) add(v, center(c[0], c[1], c[2], size), label, 1 + rng() % 5);
  }
  for (int i = 0; i < 50; ++i) add(v, center(int(rng() % 300), int(rng() % 300), int(rng() % 300), size), kNoise);
  const auto obstacles = buildObstacles(v.centers, v.weights, v.labels, size);
  ASSERT_EQ(obstacles.size(), 12u);
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    EXPECT_EQ(obstacles[k].id, int(k));
    expectWraps(obstacles[k], v, size);
  }
}

// The hull is a function of the cluster's voxels: the same vertices, triangles, volume and centroid
// to the last bit whatever order the voxels come in (CGAL triangulates flat facets differently for
// another input order, and across runs with memory addresses; buildObstacles makes its output
// canonical), and with every flat facet fanned from its smallest vertex, no vertex inside a facet
// or on an edge.
TEST(Obstacles, HullDependsOnlyOnTheVoxelsNotOnTheirOrder) {
  std::mt19937 rng(11);
  Voxels v;
  const double size = 0.05;
  for (int label = 0; label < 6; ++label) {
    // Boxes (many flat facets, many coplanar corners) and random walks.
    const std::array<int, 3> at{int(rng() % 200) - 100, int(rng() % 200) - 100, int(rng() % 40)};
    if (label % 2 == 0) {
      for (int i = 0; i < 4 + label; ++i)
        for (int j = 0; j < 3 + label; ++j)
          for (int k = 0; k < 5; ++k) add(v, center(at[0] + i, at[1] + j, at[2] + k, size), label);
    } else {
      std::set<std::array<int, 3>> cells;
      std::array<int, 3> c = at;
      while (cells.size() < 300) {
        cells.insert(c);
        c[rng() % 3] += (rng() % 2) ? 1 : -1;
      }
      for (const auto& cell : cells) add(v, center(cell[0], cell[1], cell[2], size), label);
    }
  }
  const auto reference = buildObstacles(v.centers, v.weights, v.labels, size);
  ASSERT_EQ(reference.size(), 6u);
  for (int round = 0; round < 5; ++round) {
    std::vector<std::size_t> order(v.centers.size());
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    Voxels shuffled;
    for (const std::size_t i : order) add(shuffled, v.centers[i], v.labels[i], v.weights[i]);
    const auto again = buildObstacles(shuffled.centers, shuffled.weights, shuffled.labels, size);
    ASSERT_EQ(again.size(), reference.size());
    for (std::size_t k = 0; k < again.size(); ++k) {
      SCOPED_TRACE("round " + std::to_string(round) + ", obstacle " + std::to_string(k));
      EXPECT_EQ(again[k].hull.vertices, reference[k].hull.vertices);
      EXPECT_EQ(again[k].hull.triangles, reference[k].hull.triangles);
      EXPECT_EQ(again[k].volume, reference[k].volume);
      EXPECT_EQ(again[k].centroid, reference[k].centroid);
      EXPECT_EQ(again[k].footprint.polygon, reference[k].footprint.polygon);
    }
  }
  for (const auto& o : reference) {
    SCOPED_TRACE("obstacle " + std::to_string(o.id));
    expectWraps(o, v, size);
    // A box of voxels is a box: 8 vertices, 12 triangles.
    if (o.id % 2 == 0) {
      EXPECT_EQ(o.hull.vertices.size(), 8u);
      EXPECT_EQ(o.hull.triangles.size(), 12u);
    }
    // Vertices sorted; every triangle starts at its smallest vertex; triangles sorted.
    EXPECT_TRUE(std::is_sorted(o.hull.vertices.begin(), o.hull.vertices.end(), [](const V3& a, const V3& b) {
      return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z());
    }));
    for (const auto& t : o.hull.triangles) EXPECT_LT(t[0], std::min(t[1], t[2]));
    EXPECT_TRUE(std::is_sorted(o.hull.triangles.begin(), o.hull.triangles.end()));
    // Euler: a closed triangulated sphere has V - E + F = 2, E = 3F/2, so F = 2V - 4 exactly when every
    // facet is fanned from one of its corners without extra vertices (no vertex inside a facet).
    EXPECT_EQ(o.hull.triangles.size(), 2 * o.hull.vertices.size() - 4);
  }
}

TEST(Obstacles, OffLatticeAndFarFromOriginStillContained) {
  // Centres not on octomap's lattice and far from the origin (a map in UTM-like coordinates).
  Voxels v;
  const double size = 0.037;
  const V3 base(4.3e5 + 0.0123, 5.1e6 + 0.0456, 123.0071);
  std::mt19937 rng(3);
  for (int i = 0; i < 300; ++i) add(v, base + size * V3(rng() % 9, rng() % 5, rng() % 7), 5);
  const auto obstacles = buildObstacles(v.centers, v.weights, v.labels, size);
  ASSERT_EQ(obstacles.size(), 1u);
  EXPECT_EQ(obstacles[0].id, 5);
  expectWraps(obstacles[0], v, size);
}

TEST(Obstacles, HullsOfRealMapsContainEveryClusteredVoxel) {
  HULLMAP_REQUIRE_REAL_DATA(v1, "orbslam2_euroc_V1_01_MapPoints.txt");
  HULLMAP_REQUIRE_REAL_DATA(mh, "orbslam3_euroc_MH_01_mono_pointcloud.txt");
  HULLMAP_REQUIRE_REAL_DATA(mh_ref, "orbslam3_euroc_MH_01_mono_ref_pointcloud.txt");
  HULLMAP_REQUIRE_REAL_DATA(mh_traj, "orbslam3_euroc_MH_01_mono_KeyFrameTrajectory.txt");
  HULLMAP_REQUIRE_REAL_DATA(people, "pcl_five_people.pcd");
  {
    SCOPED_TRACE("ORB-SLAM2 EuRoC V1_01, points only");
    pipeline::BuildParams options;
    options.eps = 0.1;  // the classic setting: many clusters to check
    options.min_pts = 10;
    options.inputs = {v1};
    options.frame.up = mapper::UpAxis::kNegY;
    expectBuildWrapsEveryCluster(options);
  }
  {
    SCOPED_TRACE("ORB-SLAM3 EuRoC MH_01, both files, with the keyframes");
    pipeline::BuildParams options;
    options.eps = 0.1;  // the classic setting: many clusters to check
    options.min_pts = 10;
    options.inputs = {mh, mh_ref};
    options.trajectory = mh_traj;
    options.frame.up = mapper::UpAxis::kNegY;
    expectBuildWrapsEveryCluster(options);
  }
  {
    SCOPED_TRACE("PCL five people (Kinect), from the camera at the origin, 0.1 m voxels");
    pipeline::BuildParams options;
    options.min_pts = 10;
    options.inputs = {people};
    options.origin = Eigen::Vector3d::Zero();
    options.frame.up = mapper::UpAxis::kNegY;
    options.octree.resolution = 0.1;
    options.eps = 0.2;
    expectBuildWrapsEveryCluster(options);
  }
}

TEST(Obstacles, FullBlockHasExactVolumeAndCentroid) {
  Voxels v;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 5; ++k) add(v, center(i, j, k, 0.5), 0, 2);
  const auto obstacles = buildObstacles(v.centers, {}, v.labels, 0.5);
  ASSERT_EQ(obstacles.size(), 1u);
  EXPECT_NEAR(obstacles[0].volume, 2.0 * 1.5 * 2.5, 1e-12);
  EXPECT_TRUE(obstacles[0].centroid.isApprox(V3(1.0, 0.75, 1.25), 1e-12));
  EXPECT_EQ(obstacles[0].point_weight, 60u);  // empty weights: one point per voxel
  EXPECT_EQ(obstacles[0].hull.vertices.size(), 8u);
  EXPECT_EQ(obstacles[0].footprint.polygon.size(), 4u);
}

TEST(Obstacles, RejectsBadArguments) {
  Voxels v;
  add(v, V3::Zero(), 0);
  EXPECT_THROW(buildObstacles(v.centers, v.weights, v.labels, 0.0), Error);
  EXPECT_THROW(buildObstacles(v.centers, v.weights, {0, 0}, 0.1), Error);
  EXPECT_THROW(buildObstacles(v.centers, {1, 2}, v.labels, 0.1), Error);
  EXPECT_TRUE(buildObstacles(v.centers, v.weights, {kNoise}, 0.1).empty());
}

// 2D hull against the definition: a point is a vertex iff it is in the convex hull of no other
// points (no triangle or segment of other points contains it). Integer points, exact arithmetic.
TEST(ConvexHull2d, MatchesBruteForce) {
  std::mt19937 rng(11);
  auto orient = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    const double o = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    return (o > 0) - (o < 0);
  };
  auto onSegment = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return orient(a, b, p) == 0 && p.x() >= std::min(a.x(), b.x()) && p.x() <= std::max(a.x(), b.x()) &&
           p.y() >= std::min(a.y(), b.y()) && p.y() <= std::max(a.y(), b.y());
  };
  for (int round = 0; round < 300; ++round) {
    std::set<std::pair<double, double>> distinct;
    const int n = 1 + int(rng() % 25);
    for (int i = 0; i < n; ++i) distinct.insert({double(rng() % 7), double(rng() % 7)});  // many collinear
    std::vector<Eigen::Vector2d> points;
    for (const auto& [x, y] : distinct) points.emplace_back(x, y);
    std::vector<Eigen::Vector2d> input = points;
    input.insert(input.end(), points.begin(), points.end());  // duplicates too
    std::shuffle(input.begin(), input.end(), rng);
    const auto hull = hullmap::core::convexHull2d(input);

    std::set<std::pair<double, double>> expected;
    const std::size_t m = points.size();
    for (std::size_t i = 0; i < m; ++i) {
      bool covered = false;
      for (std::size_t a = 0; a < m && !covered; ++a)
        for (std::size_t b = a + 1; b < m && !covered; ++b) {
          if (a == i || b == i) continue;
          covered = onSegment(points[i], points[a], points[b]);
          for (std::size_t c = b + 1; c < m && !covered; ++c) {
            if (c == i) continue;
            const int o1 = orient(points[a], points[b], points[i]), o2 = orient(points[b], points[c], points[i]),
                      o3 = orient(points[c], points[a], points[i]);
            covered = orient(points[a], points[b], points[c]) != 0 &&
                      ((o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0));
          }
        }
      if (!covered) expected.insert({points[i].x(), points[i].y()});
    }
    std::set<std::pair<double, double>> got;
    for (const auto& p : hull) got.insert({p.x(), p.y()});
    EXPECT_EQ(got, expected) << "round " << round;
    EXPECT_EQ(got.size(), hull.size()) << "round " << round;
    if (hull.size() >= 3) {
      double area = 0;  // counter-clockwise: positive signed area
      for (std::size_t k = 0; k < hull.size(); ++k)
        area += hull[k].x() * hull[(k + 1) % hull.size()].y() - hull[k].y() * hull[(k + 1) % hull.size()].x();
      EXPECT_GT(area, 0) << "round " << round;
    }
  }
}

}  // namespace
}  // namespace hullmap::hulls
