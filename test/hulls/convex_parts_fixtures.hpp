#pragma once
// Helpers shared by hulls/convex_parts.cpp, hulls/heavy/convex_parts.cpp.

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <random>
#include <set>

#include "hullmap/core/error.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace hullmap::hulls {

namespace {
using V3 = Eigen::Vector3d;
using clustering::kNoise;
using hullmap::test::kVoxel;

inline V3 center(int i, int j, int k) { return V3(i + 0.5, j + 0.5, k + 0.5) * kVoxel; }

/// Distance from p to the union of the cubes (edge kVoxel) at `centers`: exact point-to-box, brute force.
inline double distanceToCubes(const V3& p, const std::vector<V3>& centers) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& c : centers) {
    const V3 gap = ((p - c).cwiseAbs() - V3::Constant(0.5 * kVoxel)).cwiseMax(0.0);
    best = std::min(best, gap.norm());
  }
  return best;
}

inline bool inHull(const ConvexHull& hull, const V3& p) {
  for (const auto& t : hull.triangles) {
    const V3 a = hull.vertices[std::size_t(t[0])];
    const V3 n = (hull.vertices[std::size_t(t[1])] - a).cross(hull.vertices[std::size_t(t[2])] - a);
    if (n.dot(p - a) > 1e-12 * n.norm()) return false;
  }
  return true;
}

/// The hull's least width over its facet normals (brute force over its vertices): an upper bound on
/// its least width, and the measure the split calls flat when at most T.
inline double hullWidth(const ConvexHull& hull) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : hull.triangles) {
    const V3 a = hull.vertices[std::size_t(t[0])];
    const V3 n = (hull.vertices[std::size_t(t[1])] - a).cross(hull.vertices[std::size_t(t[2])] - a).normalized();
    double lo = 0, hi = 0;
    for (const auto& v : hull.vertices) {
      lo = std::min(lo, n.dot(v - a));
      hi = std::max(hi, n.dot(v - a));
    }
    best = std::min(best, hi - lo);
  }
  return best;
}

/// The face-hole rule's oracle (ConvexPartsParams::face_holes), brute force over the hull's triangles
/// and the part's cubes: x lies within T of the plane of a facet of the hull, and a cube of the part
/// lying within 2 voxels of that plane is within G of x.
inline bool nearAFaceVoxel(const ConvexHull& hull, const V3& x, const std::vector<V3>& own, double t, double g) {
  for (const auto& tri : hull.triangles) {
    const V3 a = hull.vertices[std::size_t(tri[0])];
    const V3 n = (hull.vertices[std::size_t(tri[1])] - a).cross(hull.vertices[std::size_t(tri[2])] - a).normalized();
    if (n.dot(a - x) > t + 1e-9) continue;
    const double half_extent = 0.5 * kVoxel * n.cwiseAbs().sum();  // a cube's deepest corner below its centre
    for (const auto& c : own) {
      if (n.dot(a - c) + half_extent > 2 * kVoxel + 1e-9) continue;
      const V3 gap = ((x - c).cwiseAbs() - V3::Constant(0.5 * kVoxel)).cwiseMax(0.0);
      if (gap.norm() <= g + 1e-9) return true;
    }
  }
  return false;
}

/// Points of the hull: its vertices, points on its triangles, and points inside (rejection in its box).
inline std::vector<V3> sampleHull(const ConvexHull& hull, std::size_t inside_count, std::mt19937& rng) {
  std::vector<V3> out(hull.vertices.begin(), hull.vertices.end());
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const auto& t : hull.triangles)
    for (int s = 0; s < 20; ++s) {
      double a = u(rng), b = u(rng);
      if (a + b > 1) {
        a = 1 - a;
        b = 1 - b;
      }
      const V3& p = hull.vertices[std::size_t(t[0])];
      out.push_back(p + a * (hull.vertices[std::size_t(t[1])] - p) + b * (hull.vertices[std::size_t(t[2])] - p));
    }
  V3 lo = hull.vertices[0], hi = hull.vertices[0];
  for (const auto& v : hull.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  for (std::size_t tries = 0, got = 0; got < inside_count && tries < 50 * inside_count; ++tries) {
    const V3 p = lo + (hi - lo).cwiseProduct(hullmap::test::drawPoint([&] { return u(rng); }));
    if (inHull(hull, p)) {
      out.push_back(p);
      ++got;
    }
  }
  return out;
}

struct Split {
  std::vector<Obstacle> obstacles;
  ConvexPartsSummary summary;
  std::vector<V3> centers;
  std::vector<std::int32_t> labels;
};

/// One cluster of all `centers`, split.
inline Split splitOne(const std::vector<V3>& centers, const ConvexPartsParams& params = {},
                      const KnownFreeSpace& known = {}) {
  Split s;
  s.centers = centers;
  s.labels.assign(centers.size(), 0);
  s.obstacles = buildObstacles(centers, {}, s.labels, kVoxel);
  s.summary = addConvexParts(s.obstacles, centers, {}, s.labels, kVoxel, params, known);
  return s;
}

/// The oracle: every sampled point of every part's hull is within T (and within the part's
/// certified bound) of that part's own voxel cubes, or, in a part that passed by the face-hole rule,
/// near a face voxel (nearAFaceVoxel); the parts partition the cluster.
inline void expectWithinConcavity(const std::vector<V3>& centers, double t, const ConvexPartsParams& params = {},
                                  const std::vector<V3>& keyframes = {}) {
  const auto groups = splitConvexParts(centers, kVoxel, params, keyframes);
  std::vector<int> seen(centers.size(), 0);
  for (const auto& g : groups)
    for (const auto i : g) ++seen[i];
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; })) << "not a partition";
  Split s = splitOne(centers, params, KnownFreeSpace{keyframes, {}});
  ASSERT_EQ(s.obstacles.size(), 1u);
  ASSERT_EQ(s.obstacles[0].parts.size(), groups.size());
  std::mt19937 rng(7);
  for (std::size_t p = 0; p < groups.size(); ++p) {
    SCOPED_TRACE("part " + std::to_string(p));
    std::vector<V3> own;
    for (const auto i : groups[p]) own.push_back(centers[i]);
    const ObstaclePart& part = s.obstacles[0].parts[p];
    EXPECT_EQ(part.voxel_count, own.size());
    // A flat part: its hull at most T thick (the oracle: its least width over its facet normals,
    // from its vertices), and bounded by the flat gap G instead of T.
    // With adapt_flat_gap, G is the cluster's adapted one (its oracle: AdaptedFlatGapMatchesItsDefinition).
    const double g =
        params.adapt_flat_gap ? adaptedFlatGap(centers, kVoxel, params) : std::max(t, params.flat_gap.value_or(t));
    if (part.flat) {
      EXPECT_GT(g, t) << "flat part without a flat gap";
      EXPECT_LE(hullWidth(part.hull), t + 1e-9);
    }
    EXPECT_LE(part.concavity_bound, (part.flat || part.faces ? g : t) + 1e-12);
    if (part.faces) {
      EXPECT_TRUE(params.face_holes);
      EXPECT_FALSE(part.flat);
    }
    // A filled part's bound counts the inside of its shell (expectWithinSolidBox is its oracle).
    if (part.filled) continue;
    double worst = 0.0;
    for (const auto& x : sampleHull(part.hull, 400, rng)) {
      const double d = distanceToCubes(x, own);
      worst = std::max(worst, d);
      if (part.faces && d > t + 1e-9) {
        EXPECT_TRUE(nearAFaceVoxel(part.hull, x, own, t, g)) << x.transpose() << " is " << d << " from the voxels";
      }
    }
    EXPECT_LE(worst, part.concavity_bound + 1e-9);
    // The bound is at most sqrt(3)/2 voxel above the truth, the sampling misses a little more.
    EXPECT_GE(worst, part.concavity_bound - 0.87 * kVoxel - 0.5 * kVoxel);
    for (const auto& k : keyframes) {
      const bool in_voxel = distanceToCubes(k, own) == 0.0;
      if (!in_voxel) {
        EXPECT_FALSE(inHull(part.hull, k)) << "keyframe " << k.transpose() << " in a hull";
      }
    }
  }
}

/// Two sparse walls meeting in a corner, as a room's: 3 m long, 2 m high, each cell of their
/// 3-voxel-thick slabs (noise spreads a wall's points over about that) occupied with probability
/// 1 / `one_in`; the corner's 3 x 3 column belongs to both slabs.
inline std::vector<V3> sparseCorner(unsigned seed, int one_in) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, one_in - 1);
  std::vector<V3> c;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j)
      if (i < 3 || j < 3)
        for (int k = 0; k < 40; ++k)
          if (pick(rng) == 0) c.push_back(center(i, j, k));
  return c;
}

}  // namespace
}  // namespace hullmap::hulls
