// Convex parts: every part's hull within T of its own voxel cubes (brute-force oracle on sampled
// hull points), the expected parts for a ring of walls, an L, a box and a table, keyframes kept out
// of hulls, determinism.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <random>
#include <set>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "test_support.hpp"

namespace hullmap::hulls {
namespace {

using V3 = Eigen::Vector3d;
using clustering::kNoise;
using hullmap::test::kVoxel;

V3 center(int i, int j, int k) { return V3(i + 0.5, j + 0.5, k + 0.5) * kVoxel; }

/// Distance from p to the union of the cubes (edge kVoxel) at `centers`: exact point-to-box, brute force.
double distanceToCubes(const V3& p, const std::vector<V3>& centers) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& c : centers) {
    const V3 gap = ((p - c).cwiseAbs() - V3::Constant(0.5 * kVoxel)).cwiseMax(0.0);
    best = std::min(best, gap.norm());
  }
  return best;
}

bool inHull(const ConvexHull& hull, const V3& p) {
  for (const auto& t : hull.triangles) {
    const V3 a = hull.vertices[std::size_t(t[0])];
    const V3 n = (hull.vertices[std::size_t(t[1])] - a).cross(hull.vertices[std::size_t(t[2])] - a);
    if (n.dot(p - a) > 1e-12 * n.norm()) return false;
  }
  return true;
}

/// The hull's least width over its facet normals (brute force over its vertices): an upper bound on
/// its least width, and the measure the split calls flat when at most T.
double hullWidth(const ConvexHull& hull) {
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
bool nearAFaceVoxel(const ConvexHull& hull, const V3& x, const std::vector<V3>& own, double t, double g) {
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
std::vector<V3> sampleHull(const ConvexHull& hull, std::size_t inside_count, std::mt19937& rng) {
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
Split splitOne(const std::vector<V3>& centers, const ConvexPartsParams& params = {}, const KnownFreeSpace& known = {}) {
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
void expectWithinConcavity(const std::vector<V3>& centers, double t, const ConvexPartsParams& params = {},
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
std::vector<V3> sparseCorner(unsigned seed, int one_in) {
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

/// The hulls representing each wall (sim::evaluate's TruthScore::parts) of a generated room
/// with no furniture at `density` points per m^2, built as `hullmap build --trajectory --align` at
/// the defaults, with `parts` as convex parts' settings (flat_gap unset: auto).
std::vector<std::size_t> wallParts(std::uint64_t seed, double density, const ConvexPartsParams& parts) {
  sim::SceneParams scene_params;
  scene_params.layout = sim::SceneLayout::kRoom;
  scene_params.seed = seed;
  scene_params.obstacles = 0;
  scene_params.density = density;
  const sim::Scene scene = sim::generateScene(scene_params);
  const auto dir =
      hullmap::test::freshDir("convex_parts_room_" + std::to_string(seed) + "_" + std::to_string(int(density)));
  sim::writeScene(scene, scene_params, dir.string());
  pipeline::BuildParams build;
  build.inputs = {dir / "map_points.txt"};
  build.trajectory = dir / "KeyFrameTrajectory.txt";
  build.align = pipeline::AlignSettings{dir / "reference_trajectory.txt", {}, {}};
  build.convex_parts = parts;
  const pipeline::BuildResult r = pipeline::build(build);
  // The scene's points in the z-up metric frame of the truth (the generator's output frame undone).
  std::vector<V3> points;
  for (const auto& p : scene.points)
    points.push_back(scene.output_rotation.transpose() * (p - scene.output_translation) / scene.output_scale);
  const sim::Evaluation e = sim::evaluate(r.obstacles, sim::readGroundTruth((dir / "ground_truth.json").string()),
                                          points, {}, sim::EvaluateParams{});
  std::vector<std::size_t> walls;
  for (const auto& t : e.truth)
    if (!t.surface) walls.push_back(t.parts.size());
  return walls;
}

TEST(ConvexParts, WallVoxelsCutOffWithAStrayGoBackToTheWall) {
  // A corner of two sparse walls with 12 strays 3 to 13 cells off them, most at the walls' foot (as a
  // room's noise lies). The split can cut a few voxels of a wall off together with a stray in line
  // with them: a thin part too (at right angles to the wall, or level), whose hull out to the stray
  // is free space. absorb gives such a flat fragment's voxels in a wall's slab back to the wall when
  // both sides still pass, and the stray is left a part of its own. Over these 20 corners, flat parts
  // holding both wall voxels and strays: 5 before (of 1+4, 1+1, 4+2, 15+1 and 31+5 voxels), 1 now:
  // seed 5's level sheet of a wall's foot and 5 strays on the floor by it, which the 5 strays alone
  // do not pass. Every part stays within its bound (the oracle).
  ConvexPartsParams params;
  params.flat_gap = 0.4;
  std::size_t flat_mixed = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    auto c = sparseCorner(seed, 20);
    std::mt19937 rng(seed + 100);
    std::uniform_int_distribution<int> along(5, 59), off(5, 16), height(0, 39);
    for (int s = 0; s < 12; ++s) {
      const int a = along(rng), o = off(rng), k = height(rng) < 20 ? height(rng) % 3 : height(rng);
      c.push_back(s % 2 ? center(a, o, k) : center(o, a, k));
    }
    const auto groups = splitConvexParts(c, kVoxel, params, {});
    const Split split = splitOne(c, params);
    ASSERT_EQ(split.obstacles[0].parts.size(), groups.size());
    for (std::size_t p = 0; p < groups.size(); ++p) {
      std::size_t wall = 0, stray = 0;
      for (const auto i : groups[p]) ++(c[i].x() < 3 * kVoxel || c[i].y() < 3 * kVoxel ? wall : stray);
      if (wall > 0 && stray > 0 && split.obstacles[0].parts[p].flat) {
        ++flat_mixed;
        std::cout << "seed " << seed << ": a flat part of " << wall << " wall voxels and " << stray << " strays\n";
      }
    }
    if (seed <= 4) expectWithinConcavity(c, 0.15, params);
  }
  EXPECT_LE(flat_mixed, 1u);
}

TEST(ConvexParts, SparseRoomsWallsAreAboutOnePartEach) {
  // Walls of generated rooms at 30 points/m^2 (the sparsest of the quality scenes), at the defaults:
  // at most 1.5 hulls per wall on average (issue 13's target), and no wall in more than 3. With G
  // fixed at the eps (the flat gap given, not adapted) the same walls split at their chance holes.
  std::size_t adapted_total = 0, fixed_total = 0, walls = 0;
  for (const std::uint64_t seed : {2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto parts = wallParts(seed, 30.0, {});
    ASSERT_EQ(parts.size(), 4u);
    for (const auto n : parts) {
      EXPECT_GE(n, 1u);
      EXPECT_LE(n, 3u);
      adapted_total += n;
    }
    walls += parts.size();
    ConvexPartsParams fixed;
    fixed.flat_gap = 0.4;  // the eps these rooms get (auto: 0.52 m clamped to 8 voxels)
    for (const auto n : wallParts(seed, 30.0, fixed)) fixed_total += n;
  }
  std::cout << "walls " << walls << ": hulls " << adapted_total << " (adapted G), " << fixed_total << " (fixed G)\n";
  EXPECT_LE(double(adapted_total), 1.5 * double(walls));
  EXPECT_GT(fixed_total, adapted_total);
}

}  // namespace
}  // namespace hullmap::hulls
