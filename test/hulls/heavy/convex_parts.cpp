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

#include "convex_parts_fixtures.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/sim/evaluate.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "test_support.hpp"

namespace hullmap::hulls {
namespace {

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
