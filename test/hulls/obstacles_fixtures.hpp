#pragma once
// Helpers shared by hulls/obstacles.cpp, hulls/heavy/obstacles.cpp.

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <tuple>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/convex_hull_2d.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace hullmap::hulls {

namespace {
using V3 = Eigen::Vector3d;
using clustering::kNoise;

struct Voxels {
  std::vector<V3> centers;
  std::vector<std::uint32_t> weights;
  std::vector<std::int32_t> labels;
};

inline void add(Voxels& v, const V3& c, std::int32_t label, std::uint32_t weight = 1) {
  v.centers.push_back(c);
  v.labels.push_back(label);
  v.weights.push_back(weight);
}

inline std::vector<V3> corners(const V3& c, double size) {
  std::vector<V3> out;
  for (int m = 0; m < 8; ++m) out.push_back(c + 0.5 * size * V3(m & 1 ? 1 : -1, m & 2 ? 1 : -1, m & 4 ? 1 : -1));
  return out;
}

/// Largest signed distance of p outside the hull's triangle planes (<= 0: inside or on).
inline double outside(const ConvexHull& hull, const V3& p) {
  double worst = -std::numeric_limits<double>::infinity();
  for (const auto& t : hull.triangles) {
    const V3 a = hull.vertices[t[0]];
    const V3 n = (hull.vertices[t[1]] - a).cross(hull.vertices[t[2]] - a).normalized();
    worst = std::max(worst, n.dot(p - a));
  }
  return worst;
}

/// Every property the issue asks of an obstacle, against its own voxels.
inline void expectWraps(const Obstacle& o, const Voxels& v, double size) {
  SCOPED_TRACE("obstacle " + std::to_string(o.id));
  const double tol = 1e-12 * std::max(1.0, o.aabb_max.cwiseAbs().maxCoeff());
  std::size_t count = 0;
  std::uint64_t weight = 0;
  std::set<std::array<double, 3>> all_corners;
  V3 lo = V3::Constant(1e300), hi = V3::Constant(-1e300);
  for (std::size_t i = 0; i < v.centers.size(); ++i) {
    if (v.labels[i] != o.id) continue;
    ++count;
    weight += v.weights[i];
    for (const V3& c : corners(v.centers[i], size)) {
      // Containment: all 8 corners inside or on the hull.
      ASSERT_LE(outside(o.hull, c), tol) << "corner " << c.transpose() << " of voxel " << i;
      all_corners.insert({c.x(), c.y(), c.z()});
      lo = lo.cwiseMin(c);
      hi = hi.cwiseMax(c);
    }
  }
  EXPECT_EQ(o.voxel_count, count);
  EXPECT_EQ(o.point_weight, weight);
  EXPECT_TRUE(o.aabb_min.isApprox(lo, 1e-12) || (o.aabb_min - lo).norm() < tol);
  EXPECT_TRUE((o.aabb_max - hi).norm() < tol);
  // Tight: each hull vertex is a voxel corner (the hull is that of the corners, no bigger).
  for (const V3& h : o.hull.vertices) {
    bool found = false;
    for (const auto& c : all_corners) found = found || (h - V3(c[0], c[1], c[2])).norm() < tol;
    EXPECT_TRUE(found) << "hull vertex " << h.transpose() << " is no voxel corner";
  }
  // Convex and outward: every vertex behind every triangle's plane; a closed, oriented mesh.
  for (const V3& h : o.hull.vertices) EXPECT_LE(outside(o.hull, h), tol);
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : o.hull.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u) << "edge without its twin";
  }
  EXPECT_GE(o.volume, double(count) * size * size * size * (1 - 1e-9));
  EXPECT_LE(o.volume, (hi - lo).prod() * (1 + 1e-9));
  EXPECT_LE(outside(o.hull, o.centroid), 0.0);
  // Footprint: counter-clockwise, contains every corner's xy, vertices are corners, z range.
  const auto& poly = o.footprint.polygon;
  ASSERT_GE(poly.size(), 3u);
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const Eigen::Vector2d a = poly[k], b = poly[(k + 1) % poly.size()];
    for (const auto& c : all_corners) {
      const double cross = (b - a).x() * (c[1] - a.y()) - (b - a).y() * (c[0] - a.x());
      EXPECT_GE(cross, -tol) << "corner outside footprint edge " << k;
    }
  }
  EXPECT_NEAR(o.footprint.z_min, lo.z(), tol);
  EXPECT_NEAR(o.footprint.z_max, hi.z(), tol);
}

/// The obstacles `hullmap build` makes of a map, checked against their voxels as above.
inline void expectBuildWrapsEveryCluster(const pipeline::BuildParams& params) {
  const pipeline::BuildResult r = pipeline::build(params);
  Voxels v;
  for (std::size_t i = 0; i < r.voxels.size(); ++i)
    add(v, r.voxels[i].center, r.clusters.labels[i], r.voxels[i].weight);
  ASSERT_GT(r.obstacles.size(), 5u);
  std::size_t clustered = 0;
  for (const auto& o : r.obstacles) {
    expectWraps(o, v, r.map.resolution());
    clustered += o.voxel_count;
  }
  // Floor and ceiling voxels are in no cluster and not noise (their rims next to a cluster joined it).
  EXPECT_EQ(clustered + r.clusters.noise + r.report.floor.voxels + r.report.ceiling.voxels, r.voxels.size());
}

}  // namespace
}  // namespace hullmap::hulls
