// Sparse edges: a sparse part grows in its own plane by the share of its spacing the header names,
// no thicker, its hull written the same whatever the process (sparse_edges.hpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <thread>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <gtest/gtest.h>

#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/hulls/sparse_edges.hpp"

namespace {

using hullmap::hulls::ConvexHull;
using hullmap::hulls::ObstaclePart;
using V3 = Eigen::Vector3d;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

constexpr double kVoxel = 0.05;

/// One part: the whole obstacle of `centers` (buildObstacles, weights 1 each), as a part.
ObstaclePart partOf(const std::vector<V3>& centers, std::uint32_t weight) {
  const std::vector<std::int32_t> labels(centers.size(), 0);
  const std::vector<std::uint32_t> weights(centers.size(), weight);
  const auto o = hullmap::hulls::buildObstacles(centers, weights, labels, kVoxel).at(0);
  ObstaclePart p;
  p.voxel_count = o.voxel_count;
  p.point_weight = o.point_weight;
  p.aabb_min = o.aabb_min;
  p.aabb_max = o.aabb_max;
  p.centroid = o.centroid;
  p.volume = o.volume;
  p.hull = o.hull;
  p.footprint = o.footprint;
  return p;
}

/// A table top 1.2 x 0.8 m, one voxel thick, at 0.7 m: a voxel every `every` cells along x and y.
std::vector<V3> tableTop(int every) {
  std::vector<V3> c;
  for (int i = 0; i < 24; i += every)
    for (int j = 0; j < 16; j += every) c.emplace_back((i + 0.5) * kVoxel, (j + 0.5) * kVoxel, 0.725);
  c.emplace_back(23.5 * kVoxel, 15.5 * kVoxel, 0.725);  // its far corner seen
  return c;
}

double distanceOutside(const ConvexHull& hull, const V3& p) {
  // Largest signed distance to the hull's facet planes: > 0 outside.
  double worst = -1e300;
  for (const auto& t : hull.triangles) {
    const V3 a = hull.vertices[t[0]], b = hull.vertices[t[1]], c = hull.vertices[t[2]];
    const V3 n = (b - a).cross(c - a);
    if (n.norm() < 1e-15) continue;
    worst = std::max(worst, n.normalized().dot(p - a));
  }
  return worst;
}

/// The area of the points' 2D hull, by CGAL (the oracle: the library sums its own shoelace).
double hullArea2d(std::vector<Eigen::Vector2d> points) {
  std::vector<Kernel::Point_2> polygon;
  for (const auto& p : hullmap::core::convexHull2d(std::move(points))) polygon.emplace_back(p.x(), p.y());
  return std::abs(CGAL::polygon_area_2(polygon.begin(), polygon.end(), Kernel()));
}

}  // namespace

TEST(SparseEdges, ADenseTopKeepsItsHull) {
  const ObstaclePart dense = partOf(tableTop(1), 2);
  ObstaclePart grown = dense;
  EXPECT_EQ(hullmap::hulls::growSparseEdges(grown, kVoxel), 0.0);
  EXPECT_EQ(grown.hull.vertices, dense.hull.vertices);
  EXPECT_EQ(grown.hull.triangles, dense.hull.triangles);
  EXPECT_EQ(grown.volume, dense.volume);
}

TEST(SparseEdges, ASparseTopGrowsInItsPlaneByItsSpacing) {
  const ObstaclePart sparse = partOf(tableTop(4), 1);
  // The oracle: the top's area in its plane (z up), its points, the growth the header gives.
  std::vector<Eigen::Vector2d> flat;
  for (const auto& v : sparse.hull.vertices) flat.push_back(v.head<2>());
  const double spacing = std::sqrt(hullArea2d(flat) / double(sparse.point_weight));
  const hullmap::hulls::SparseEdges params;
  const double expected = std::min(params.cap * kVoxel, params.factor * (spacing - params.onset * kVoxel));
  ASSERT_GT(expected, 0.0) << "spacing " << spacing;
  EXPECT_NEAR(hullmap::hulls::sparseEdgeGrowth(sparse, kVoxel), expected, 1e-12);

  ObstaclePart grown = sparse;
  const double d = hullmap::hulls::growSparseEdges(grown, kVoxel);
  EXPECT_NEAR(d, expected, 1e-12);
  // No thicker, and everything it held it holds.
  EXPECT_NEAR(grown.aabb_min.z(), sparse.aabb_min.z(), 1e-12);
  EXPECT_NEAR(grown.aabb_max.z(), sparse.aabb_max.z(), 1e-12);
  for (const auto& v : sparse.hull.vertices) EXPECT_LE(distanceOutside(grown.hull, v), 1e-12);
  // Every point of the old hull moved by d in any horizontal direction is inside, up to the
  // 12-gon's shortfall from a circle (1 - cos 15 deg); no new vertex is farther than d from it.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * M_PI);
  const double gon = d * (1.0 - std::cos(M_PI / 12.0)) + 1e-12;
  for (const auto& v : sparse.hull.vertices)
    for (int k = 0; k < 8; ++k) {
      const double a = angle(rng);
      EXPECT_LE(distanceOutside(grown.hull, v + d * V3(std::cos(a), std::sin(a), 0.0)), gon);
    }
  for (const auto& v : grown.hull.vertices) EXPECT_LE(distanceOutside(sparse.hull, v), d + 1e-12);
  // Box, footprint, volume follow the hull; counts stay.
  for (const auto& v : grown.hull.vertices) {
    EXPECT_TRUE((v.array() >= grown.aabb_min.array() - 1e-15).all() &&
                (v.array() <= grown.aabb_max.array() + 1e-15).all());
  }
  EXPECT_GT(grown.volume, sparse.volume);
  const double thickness = sparse.aabb_max.z() - sparse.aabb_min.z();
  std::vector<Eigen::Vector2d> grown_flat;
  for (const auto& v : grown.hull.vertices) grown_flat.push_back(v.head<2>());
  EXPECT_NEAR(grown.volume, hullArea2d(grown_flat) * thickness, 1e-12);
  EXPECT_NEAR(hullArea2d(grown.footprint.polygon), hullArea2d(grown_flat), 1e-12);
  EXPECT_EQ(grown.voxel_count, sparse.voxel_count);
  EXPECT_EQ(grown.point_weight, sparse.point_weight);
}

TEST(SparseEdges, AWallGrowsAlongItselfNotIntoTheRoom) {
  // A sparse wall 2 m long (x), 2 m high, one voxel thick (y).
  std::vector<V3> c;
  for (int i = 0; i < 40; i += 4)
    for (int k = 0; k < 40; k += 4) c.emplace_back((i + 0.5) * kVoxel, 0.025, (k + 0.5) * kVoxel);
  const ObstaclePart wall = partOf(c, 1);
  ObstaclePart grown = wall;
  const double d = hullmap::hulls::growSparseEdges(grown, kVoxel);
  ASSERT_GT(d, 0.0);
  EXPECT_NEAR(grown.aabb_min.y(), wall.aabb_min.y(), 1e-9);
  EXPECT_NEAR(grown.aabb_max.y(), wall.aabb_max.y(), 1e-9);
  EXPECT_NEAR(grown.aabb_max.x(), wall.aabb_max.x() + d, 1e-9);
  EXPECT_NEAR(grown.aabb_min.z(), wall.aabb_min.z() - d, 1e-9);
}

TEST(SparseEdges, TheHullIsWrittenTheSameWhateverTheProcessDid) {
  // CGAL orders the hull's vertices and faces by addresses: the canonical form must not.
  const ObstaclePart sparse = partOf(tableTop(4), 1);
  ObstaclePart first = sparse;
  hullmap::hulls::growSparseEdges(first, kVoxel);
  std::vector<std::vector<char>> clutter;
  for (int round = 0; round < 5; ++round) {
    for (int k = 0; k < 50; ++k) clutter.emplace_back(std::size_t(17 * k + 1));
    if (round % 2) clutter.erase(clutter.begin(), clutter.begin() + 30);
    ObstaclePart again = sparse;
    std::thread([&] { hullmap::hulls::growSparseEdges(again, kVoxel); }).join();
    EXPECT_EQ(again.hull.vertices, first.hull.vertices) << round;
    EXPECT_EQ(again.hull.triangles, first.hull.triangles) << round;
  }
  // Each face a fan from its smallest vertex: every triangle starts at its smallest index, and the
  // mesh is closed (every edge once each way).
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : first.hull.triangles) {
    EXPECT_LT(t[0], t[1]);
    EXPECT_LT(t[0], t[2]);
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
}

TEST(SparseEdges, RejectsBadParameters) {
  ObstaclePart p = partOf(tableTop(4), 1);
  hullmap::hulls::SparseEdges bad;
  bad.factor = -1.0;
  EXPECT_THROW(hullmap::hulls::growSparseEdges(p, kVoxel, bad), hullmap::Error);
  EXPECT_THROW(hullmap::hulls::growSparseEdges(p, 0.0), hullmap::Error);
  bad = {};
  bad.cap = std::nan("");
  EXPECT_THROW(hullmap::hulls::sparseEdgeGrowth(p, kVoxel, bad), hullmap::Error);
}
