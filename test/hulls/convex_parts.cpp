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

/// Cells of the box [i0, i1) x [j0, j1) x [k0, k1), appended to `out` without duplicates.
void addBox(std::vector<V3>& out, int i0, int i1, int j0, int j1, int k0, int k1) {
  std::set<std::tuple<double, double, double>> have;
  for (const auto& c : out) have.insert({c.x(), c.y(), c.z()});
  for (int i = i0; i < i1; ++i)
    for (int j = j0; j < j1; ++j)
      for (int k = k0; k < k1; ++k) {
        const V3 c = center(i, j, k);
        if (have.insert({c.x(), c.y(), c.z()}).second) out.push_back(c);
      }
}

std::vector<V3> ring() {  // a room's walls: 2 m square, 10 cm thick, 1 m high
  std::vector<V3> c;
  addBox(c, 0, 40, 0, 2, 0, 20);
  addBox(c, 0, 40, 38, 40, 0, 20);
  addBox(c, 0, 2, 0, 40, 0, 20);
  addBox(c, 38, 40, 0, 40, 0, 20);
  return c;
}

std::vector<V3> lShape() {  // a shelf: 1.5 m and 1 m arms, 20 cm deep, 1 m high
  std::vector<V3> c;
  addBox(c, 0, 30, 0, 4, 0, 20);
  addBox(c, 0, 4, 0, 20, 0, 20);
  return c;
}

std::vector<V3> table() {  // a 1 x 0.6 m top, 5 cm thick, 75 cm up, on four 10 cm legs
  std::vector<V3> c;
  addBox(c, 0, 20, 0, 12, 14, 15);
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{0, 0}, {18, 0}, {0, 10}, {18, 10}})
    addBox(c, i, i + 2, j, j + 2, 0, 14);
  return c;
}

TEST(ConvexParts, DefaultIsThreeVoxels) { EXPECT_DOUBLE_EQ(defaultConcavity(0.05), 0.15); }

TEST(ConvexParts, BoxStaysOnePart) {
  std::vector<V3> c;
  addBox(c, 0, 20, 0, 12, 0, 16);
  const Split s = splitOne(c);
  ASSERT_EQ(s.obstacles[0].parts.size(), 1u);
  EXPECT_NEAR(s.obstacles[0].parts[0].volume, s.obstacles[0].volume, 1e-12);
  EXPECT_EQ(s.obstacles[0].parts[0].concavity_bound, 0.0);
  expectWithinConcavity(c, 0.15);
}

TEST(ConvexParts, SlantedSparseWallStaysOnePart) {
  // A wall at about 30 degrees, one voxel thick, with every third voxel missing: sparse, not axis-aligned.
  std::vector<V3> c;
  for (int s = 0; s < 60; ++s)
    for (int k = 0; k < 20; ++k)
      if ((s + k) % 3 != 0) addBox(c, s, s + 1, int(std::lround(s * 0.577)), int(std::lround(s * 0.577)) + 1, k, k + 1);
  const Split s = splitOne(c);
  EXPECT_EQ(s.obstacles[0].parts.size(), 1u);
  expectWithinConcavity(c, 0.15);
}

/// A sparse wall as SLAM leaves it: one cell in 12 of a 3 m x 2 m slab two voxels thick (holes up to
/// about 0.3 m across), seeded.
std::vector<V3> sparseWall(unsigned seed, int i0 = 0, int j0 = 0, bool along_x = true) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, 11);
  std::vector<V3> c;
  for (int a = 0; a < 60; ++a)
    for (int b = 0; b < 2; ++b)
      for (int k = 0; k < 40; ++k)
        if (pick(rng) == 0) c.push_back(along_x ? center(i0 + a, j0 + b, k) : center(i0 + b, j0 + a, k));
  return c;
}

TEST(ConvexParts, SparseWallShattersWithoutAFlatGap) {
  const auto c = sparseWall(3);
  const Split s = splitOne(c);
  EXPECT_GT(s.obstacles[0].parts.size(), 10u);
  EXPECT_EQ(s.summary.flat_parts, 0u);
  EXPECT_DOUBLE_EQ(s.summary.flat_gap, 0.15);
  expectWithinConcavity(c, 0.15);
}

TEST(ConvexParts, SparseWallStaysOnePartWithAFlatGap) {
  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = sparseWall(seed);
    ConvexPartsParams params;
    params.flat_gap = 0.4;
    const Split s = splitOne(c, params);
    ASSERT_EQ(s.obstacles[0].parts.size(), 1u);
    EXPECT_TRUE(s.obstacles[0].parts[0].flat);
    EXPECT_GT(s.obstacles[0].parts[0].concavity_bound, 0.15);
    EXPECT_EQ(s.summary.flat_parts, 1u);
    EXPECT_DOUBLE_EQ(s.summary.flat_gap, 0.4);
    expectWithinConcavity(c, 0.15, params);
  }
}

TEST(ConvexParts, FlatGapKeepsOutliersOffTheWall) {
  // Two outlier voxels 0.3 m in front of the wall: a part holding one is no longer flat, so it
  // must pass T; the wall's part stays within a voxel or two of its slab.
  auto c = sparseWall(4);
  c.push_back(center(20, 8, 20));
  c.push_back(center(45, 8, 10));
  ConvexPartsParams params;
  params.flat_gap = 0.4;
  const Split s = splitOne(c, params);
  std::size_t flat = 0;
  for (const auto& part : s.obstacles[0].parts)
    if (part.flat) {
      ++flat;
      EXPECT_LE(part.aabb_max.y(), 2 * kVoxel + 1e-9) << "a flat part reaches an outlier";
    }
  EXPECT_GE(flat, 1u);
  expectWithinConcavity(c, 0.15, params);
}

TEST(ConvexParts, SparseRingBecomesItsWallsWithAFlatGap) {
  // Four sparse 3 m walls around a square: the flat gap must not join them into a ring's hull.
  std::vector<V3> c;
  for (const auto& w :
       {sparseWall(5, 0, 0, true), sparseWall(6, 0, 58, true), sparseWall(7, 0, 0, false), sparseWall(8, 58, 0, false)})
    c.insert(c.end(), w.begin(), w.end());
  std::sort(c.begin(), c.end(),
            [](const V3& a, const V3& b) { return std::tie(a.x(), a.y(), a.z()) < std::tie(b.x(), b.y(), b.z()); });
  c.erase(std::unique(c.begin(), c.end()), c.end());
  ConvexPartsParams params;
  params.flat_gap = 0.4;
  const Split s = splitOne(c, params);
  EXPECT_GE(s.obstacles[0].parts.size(), 4u);
  EXPECT_LE(s.obstacles[0].parts.size(), 16u);
  // Nothing swallows the room: every part's hull is thin in x or y.
  for (const auto& part : s.obstacles[0].parts) {
    const V3 size = part.aabb_max - part.aabb_min;
    EXPECT_LE(std::min(size.x(), size.y()), 0.6) << "a part spans the room";
  }
  expectWithinConcavity(c, 0.15, params);
}

/// A wall as a sparse SLAM map leaves it, one voxel thick: each cell of the `width` x `height` cell
/// slab (x, z; at y cell 0) occupied with probability 1 / `one_in` (seeded), except the cells of the
/// opening [door_i0, door_i1) x [0, door_k1) (none when door_i1 <= door_i0).
std::vector<V3> randomWall(unsigned seed, int width, int height, int one_in, int door_i0 = 0, int door_i1 = 0,
                           int door_k1 = 0) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, one_in - 1);
  std::vector<V3> c;
  for (int i = 0; i < width; ++i)
    for (int k = 0; k < height; ++k)
      if (pick(rng) == 0 && !(i >= door_i0 && i < door_i1 && k < door_k1)) c.push_back(center(i, 0, k));
  return c;
}

/// adaptedFlatGap's rule, brute force: neighbours within G of every stride-th voxel by a scan of all
/// voxels, their lower quartile, and the chance radius by bisection on N x e^-x = 0.01.
double adaptedFlatGapOracle(const std::vector<V3>& c, double t, double g) {
  const std::size_t stride = (c.size() + 1023) / 1024;
  std::vector<std::size_t> counts;
  for (std::size_t s = 0; s < c.size(); s += stride) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < c.size(); ++i) n += i != s && (c[i] - c[s]).squaredNorm() <= g * g * (1 + 1e-9);
    counts.push_back(n);
  }
  std::sort(counts.begin(), counts.end());
  const double q = std::max(1.0, double(counts[counts.size() / 4]));
  const double lambda_pi = q / (g * g);  // per map unit^2
  double lo = 1.0, hi = 1000.0;          // x - ln x is increasing for x >= 1
  const double target = std::log(double(c.size())) - std::log(0.01);
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (mid - std::log(mid) < target ? lo : hi) = mid;
  }
  const double r = std::sqrt(lo / lambda_pi);
  return std::clamp(std::sqrt(r * r + t * t), g, 2 * g);
}

TEST(ConvexParts, AdaptedFlatGapMatchesItsDefinition) {
  ConvexPartsParams params;
  params.flat_gap = 0.3;
  params.adapt_flat_gap = true;
  for (const auto& [seed, one_in] : std::vector<std::pair<unsigned, int>>{{1, 4}, {2, 10}, {3, 16}, {4, 30}}) {
    SCOPED_TRACE("one in " + std::to_string(one_in));
    const auto c = randomWall(seed, 100, 60, one_in);
    EXPECT_NEAR(adaptedFlatGap(c, kVoxel, params), adaptedFlatGapOracle(c, 0.15, 0.3), 1e-9);
  }
  // Over 1024 voxels only every k-th is counted.
  const auto big = randomWall(5, 200, 60, 5);
  ASSERT_GT(big.size(), 2048u);
  EXPECT_NEAR(adaptedFlatGap(big, kVoxel, params), adaptedFlatGapOracle(big, 0.15, 0.3), 1e-9);
}

TEST(ConvexParts, AdaptedFlatGapGrowsOnlyOnSparseSurfaces) {
  ConvexPartsParams params;
  params.flat_gap = 0.3;
  params.adapt_flat_gap = true;
  // Dense: G. Sparser: larger, never above 2 G.
  EXPECT_DOUBLE_EQ(adaptedFlatGap(randomWall(1, 100, 60, 1), kVoxel, params), 0.3);
  const double g16 = adaptedFlatGap(randomWall(1, 100, 60, 16), kVoxel, params);
  const double g30 = adaptedFlatGap(randomWall(1, 100, 60, 30), kVoxel, params);
  EXPECT_GT(g16, 0.3);
  EXPECT_GT(g30, g16);
  EXPECT_LE(adaptedFlatGap(randomWall(1, 100, 60, 200), kVoxel, params), 0.6 + 1e-12);
  // Off, G <= T, or a handful of voxels: G as given (at least T).
  const auto sparse = randomWall(1, 100, 60, 16);
  ConvexPartsParams off = params;
  off.adapt_flat_gap = false;
  EXPECT_DOUBLE_EQ(adaptedFlatGap(sparse, kVoxel, off), 0.3);
  ConvexPartsParams small_g = params;
  small_g.flat_gap = 0.1;
  EXPECT_DOUBLE_EQ(adaptedFlatGap(sparse, kVoxel, small_g), 0.15);
  EXPECT_DOUBLE_EQ(adaptedFlatGap(std::vector<V3>(sparse.begin(), sparse.begin() + 15), kVoxel, params), 0.3);
  // A map at another monocular scale (voxels, T and G scaled alike): the same G in its units.
  std::vector<V3> scaled;
  for (const auto& p : sparse) scaled.push_back(2.7 * p);
  ConvexPartsParams at_scale = params;
  at_scale.flat_gap = 2.7 * 0.3;
  at_scale.concavity = 2.7 * 0.15;
  EXPECT_NEAR(adaptedFlatGap(scaled, 2.7 * kVoxel, at_scale), 2.7 * g16, 1e-9);
}

TEST(ConvexParts, SparseRandomWallIsOnePartWithTheAdaptedGap) {
  // A 5 m x 3 m wall at about 25 map points per m^2 (one cell in 16), the sparseness of the
  // generated rooms: its chance holes are wider than 2 G at G = 0.3, so a fixed G splits some of
  // these walls; the adapted G keeps every one whole, within the oracle's bound.
  ConvexPartsParams fixed;
  fixed.flat_gap = 0.3;
  ConvexPartsParams adapted = fixed;
  adapted.adapt_flat_gap = true;
  std::size_t split_by_fixed = 0;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = randomWall(seed, 100, 60, 16);
    split_by_fixed += splitOne(c, fixed).obstacles[0].parts.size() > 1;
    const Split s = splitOne(c, adapted);
    EXPECT_EQ(s.obstacles[0].parts.size(), 1u);
    EXPECT_GT(s.summary.flat_gap_max, 0.3);
    EXPECT_DOUBLE_EQ(s.summary.flat_gap, 0.3);
    expectWithinConcavity(c, 0.15, adapted);
  }
  EXPECT_GT(split_by_fixed, 0u) << "the walls should be too sparse for the fixed G";
}

TEST(ConvexParts, DoorwayWiderThanTwiceTheAdaptedGapIsNotBridged) {
  // A 5 m x 3 m wall at about 50 points per m^2 (one cell in 8) with a doorway 0.9 m wide and 2 m
  // high: the adapted G stays below half its width, so no hull spans the opening.
  ConvexPartsParams params;
  params.flat_gap = 0.3;
  params.adapt_flat_gap = true;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = randomWall(seed, 100, 60, 8, 40, 58, 40);
    const double g = adaptedFlatGap(c, kVoxel, params);
    ASSERT_LT(2 * g, 0.9) << "the doorway must be wider than 2 G for this test";
    const Split s = splitOne(c, params);
    // The doorway's middle, from 0.2 m up to 0.2 m under its lintel.
    for (double z = 0.2; z <= 1.8; z += 0.05)
      for (const auto& part : s.obstacles[0].parts)
        EXPECT_FALSE(inHull(part.hull, V3(49 * kVoxel, 0.5 * kVoxel, z))) << "a hull bridges the doorway at z " << z;
    expectWithinConcavity(c, 0.15, params);
  }
}

TEST(ConvexParts, CornerOfTwoSparseWallsIsTwoFlatParts) {
  // The corner's column belongs to both slabs, and the corner's voxels of both walls together are
  // thicker than T: every voxel (but an outlier or two) ends in one of two flat parts, the walls,
  // each within its bound (the oracle). (The generated rooms' corners, where noise and the split's
  // cuts leave a non-flat piece, are SparseRoomsWallsAreAboutOnePartEach.)
  ConvexPartsParams params;
  params.flat_gap = 0.4;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = sparseCorner(seed, 20);
    const Split s = splitOne(c, params);
    std::size_t in_flat = 0, big = 0;
    for (const auto& part : s.obstacles[0].parts) {
      if (part.flat) in_flat += part.voxel_count;
      big += part.voxel_count > 1;
    }
    EXPECT_EQ(big, 2u);
    EXPECT_GE(in_flat + 2, c.size());
    expectWithinConcavity(c, 0.15, params);
  }
}

/// The surface cells of the box [i0, i1) x [j0, j1) x [k0, k1) (one cell thick), without its bottom
/// face when `open_bottom`, and keeping one cell in `keep_one_in` (1: all) to make it sparse.
std::vector<V3> shell(int i0, int i1, int j0, int j1, int k0, int k1, bool open_bottom, int keep_one_in = 1,
                      unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, keep_one_in - 1);
  std::vector<V3> c;
  for (int i = i0; i < i1; ++i)
    for (int j = j0; j < j1; ++j)
      for (int k = k0; k < k1; ++k) {
        const bool surface =
            i == i0 || i == i1 - 1 || j == j0 || j == j1 - 1 || k == k1 - 1 || (k == k0 && !open_bottom);
        if (surface && pick(rng) == 0) c.push_back(center(i, j, k));
      }
  return c;
}

/// The oracle for filled parts: every sampled hull point within T of the solid box (brute force).
void expectWithinSolidBox(const Split& s, const V3& lo, const V3& hi, double t) {
  std::mt19937 rng(3);
  for (const auto& part : s.obstacles[0].parts)
    for (const auto& x : sampleHull(part.hull, 400, rng)) {
      const V3 gap = (lo - x).cwiseMax(x - hi).cwiseMax(0.0);
      EXPECT_LE(gap.norm(), t + 1e-9) << x.transpose();
    }
}

TEST(ConvexParts, ClosedShellStaysOnePart) {
  // A 0.8 x 0.6 x 1 m box seen only on its surface: its inside, never observed, is enclosed.
  const auto c = shell(0, 16, 0, 12, 0, 20, false);
  const Split s = splitOne(c);
  ASSERT_EQ(s.obstacles[0].parts.size(), 1u);
  EXPECT_TRUE(s.obstacles[0].parts[0].filled);
  expectWithinSolidBox(s, V3::Zero(), V3(16, 12, 20) * kVoxel, 0.15);
  // Without the fill it is cut into its faces.
  ConvexPartsParams off;
  off.fill_enclosed = false;
  EXPECT_GT(splitOne(c, off).obstacles[0].parts.size(), 3u);
}

/// The voxel o cells off face f (0 to 4: -x, +x, -y, +y, top) of the 24 x 20 x 24 shell below, at
/// (a, b) on that face.
V3 offTheShell(int f, int a, int b, int o) {
  const std::array<V3, 5> at{center(-o, a, b), center(23 + o, a, b), center(a, -o, b), center(a, 19 + o, b),
                             center(a, b, 23 + o)};
  return at[std::size_t(f)];
}

/// One cluster of `c` split with a flat gap of 0.3 and the floor at z = 0.
Split splitOnTheFloor(const std::vector<V3>& c) {
  ConvexPartsParams params;
  params.flat_gap = 0.3;
  params.floor_z = 0.0;
  return splitOne(c, params);
}

TEST(ConvexParts, SparseShellWithStrayVoxelsIsOnePartAndTheStrays) {
  // A 1.2 x 1 x 1.2 m box on the floor, one surface cell in 6 kept, and two stray voxels 3 to 5 (or
  // 4 to 6) cells off its faces: the whole fails (the hull's wedges out to the strays are farther
  // than T from everything). Before, the split cut the box into slices with them (3 parts and a
  // stray's piece of 19 voxels; 5 parts when the merge's pre-filter still ignored the enclosed
  // cells); now the strays are shed first (shedStrays) and the box stays one part.
  for (const auto& [seed, near_off] : {std::pair<unsigned, int>{1, 3}, {2, 3}, {1, 4}, {2, 4}}) {
    SCOPED_TRACE("seed " + std::to_string(seed) + " off " + std::to_string(near_off));
    auto c = shell(0, 24, 0, 20, 0, 24, true, 6, seed);
    const std::size_t shell_cells = c.size();
    std::mt19937 rng(seed + 10);
    std::uniform_int_distribution<int> pos(0, 19), off(near_off, near_off + 2), face(0, 4);
    for (int n = 0; n < 2; ++n) {
      const int f = face(rng), a = pos(rng), b = pos(rng), o = off(rng);
      c.push_back(offTheShell(f, a, b, o));
    }
    const Split s = splitOnTheFloor(c);
    const auto& parts = s.obstacles[0].parts;
    EXPECT_LE(parts.size(), 3u);
    // The shell is one part.
    EXPECT_TRUE(
        std::any_of(parts.begin(), parts.end(), [&](const ObstaclePart& p) { return p.voxel_count >= shell_cells; }));
    // Every part is filled or a lone stray, and within the bound.
    for (const auto& p : parts) {
      EXPECT_TRUE(p.filled || p.voxel_count == 1);
      EXPECT_LE(p.concavity_bound, (p.flat || p.faces ? 0.3 : 0.15) + 1e-12);
    }
  }
}

TEST(ConvexParts, DenseShellWithPairsOfStraysIsOnePartAndTheStrays) {
  // A densely sampled 1.2 x 1 x 1.2 m box on the floor (every surface cell) with three pairs of
  // stray voxels (two touching voxels each, as a noisy point often leaves) 6 to 9 cells off its
  // faces. A pair is not lone, so before only lone cells were shed and the split cut the box into
  // slices with the pairs; on a dense cluster (few cells in clumps of at most 3) a pair or a triple
  // is a stray too, shed whole, and the box stays one part.
  for (const unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    auto c = shell(0, 24, 0, 20, 0, 24, true, 1, seed);
    const std::size_t shell_cells = c.size();
    std::mt19937 rng(seed + 10);
    std::uniform_int_distribution<int> pos(0, 18), off(6, 9), face(0, 4);
    for (int n = 0; n < 3; ++n) {
      const int f = face(rng), a = pos(rng), b = pos(rng), o = off(rng);
      // The pair: (a, b) and (a + 1, b) on the face's plane, o cells off it.
      for (const int da : {0, 1}) c.push_back(offTheShell(f, a + da, b, o));
    }
    const Split s = splitOnTheFloor(c);
    const auto& parts = s.obstacles[0].parts;
    EXPECT_LE(parts.size(), 4u);
    EXPECT_TRUE(
        std::any_of(parts.begin(), parts.end(), [&](const ObstaclePart& p) { return p.voxel_count >= shell_cells; }))
        << parts.size() << " parts";
    for (const auto& p : parts) {
      EXPECT_TRUE(p.filled || p.voxel_count <= 2);
      EXPECT_LE(p.concavity_bound, (p.flat || p.faces ? 0.3 : 0.15) + 1e-12);
    }
  }
}

TEST(ConvexParts, ClumpOffASparseShellGivesBackTheFacesVoxels) {
  // A clump of 3 stray voxels (not lone: shedStrays leaves it) 4 to 5 cells above the sparse shell's
  // top: the split cuts it off with a slice of the top (seed 3: 12 of its voxels), and
  // absorbIntoBoxes gives the slice back to the box's part, leaving the clump a part of its own.
  // (Seed 2, not tested: the clump stays with 44 of the top's voxels, a piece too large for a
  // fragment, and the box is two parts.)
  for (const unsigned seed : {1u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    auto c = shell(0, 24, 0, 20, 0, 24, true, 6, seed);
    std::mt19937 rng(seed + 20);
    std::uniform_int_distribution<int> pos(4, 16);
    const int a = pos(rng), b = pos(rng);
    for (const auto& d : {V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 1)}) c.push_back(center(a, b, 27) + d * kVoxel);
    ConvexPartsParams params;
    params.flat_gap = 0.3;
    params.floor_z = 0.0;
    const Split s = splitOne(c, params);
    const auto& parts = s.obstacles[0].parts;
    EXPECT_LE(parts.size(), 3u);
    EXPECT_TRUE(std::any_of(parts.begin(), parts.end(), [](const ObstaclePart& p) { return p.voxel_count == 3; }));
    for (const auto& p : parts) EXPECT_LE(p.concavity_bound, (p.flat || p.faces ? 0.3 : 0.15) + 1e-12);
  }
}

TEST(ConvexParts, SparseShellOnTheFloorStaysOnePart) {
  // A 1.2 x 1 x 1 m box standing on the floor z = 0, its bottom never seen, one surface cell in 8
  // kept: the floor closes it below, the flat gap closes its holes.
  const auto c = shell(0, 24, 0, 20, 0, 20, true, 8);
  ConvexPartsParams params;
  params.flat_gap = 0.3;
  params.floor_z = 0.0;
  const Split s = splitOne(c, params);
  ASSERT_EQ(s.obstacles[0].parts.size(), 1u);
  EXPECT_TRUE(s.obstacles[0].parts[0].filled);
  expectWithinSolidBox(s, V3::Zero(), V3(24, 20, 20) * kVoxel, 0.15);
  // Far above the floor, the open bottom (wider than 2 G) lets the outside in: a cup, whose inside
  // is not enclosed (only the closing's fillets along its inner edges are), is split.
  params.floor_z = -1.0;
  EXPECT_GT(splitOne(c, params).obstacles[0].parts.size(), 1u);
}

TEST(ConvexParts, SparseBoardIsOnePartByItsFaces) {
  // A 1 x 0.2 x 1 m board (thicker than T, so not flat) seen on its surface, one cell in 6 kept,
  // nothing filled: points of its hull over the holes in its faces and along its edges are farther
  // than T from every voxel, so the check cuts it (3 to 5 parts); the face-hole rule merges the
  // pieces back into one (the oracle, nearAFaceVoxel, holds at every sampled point).
  for (const unsigned seed : {2u, 3u, 4u, 5u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = shell(0, 20, 0, 4, 0, 20, false, 6, seed);
    ConvexPartsParams params;
    params.flat_gap = 0.3;
    params.fill_enclosed = false;
    ConvexPartsParams strict = params;
    strict.face_holes = false;
    const Split before = splitOne(c, strict);
    const Split s = splitOne(c, params);
    EXPECT_GT(before.obstacles[0].parts.size(), 1u);
    EXPECT_EQ(before.summary.face_parts, 0u);
    EXPECT_EQ(s.obstacles[0].parts.size(), 1u);
    EXPECT_EQ(s.summary.face_parts, 1u);
    expectWithinConcavity(c, 0.15, params);
  }
}

TEST(ConvexParts, SparseTallBoxOnTheFloorIsOnePartByItsFaces) {
  // A 0.7 x 0.55 x 2 m box standing on the floor, its bottom never seen, one surface cell in 15
  // kept (about the generated rooms' sparse furniture): its hull's points along its sparse edges are
  // farther than T from the voxels and from the cells it encloses, so it was cut into 2 to 5 slices
  // on 11 of 12 seeds; with the face-hole rule 10 of 12 are one part. Every hull stays within the box.
  std::size_t strict_parts = 0, parts = 0, whole = 0;
  for (unsigned seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const auto c = shell(0, 14, 0, 11, 0, 40, true, 15, seed);
    ConvexPartsParams params;
    params.flat_gap = 0.3;
    params.floor_z = 0.0;
    ConvexPartsParams strict = params;
    strict.face_holes = false;
    const Split s = splitOne(c, params);
    strict_parts += splitOne(c, strict).obstacles[0].parts.size();
    parts += s.obstacles[0].parts.size();
    whole += s.obstacles[0].parts.size() == 1;
    for (const auto& p : s.obstacles[0].parts) EXPECT_LE(p.concavity_bound, (p.flat || p.faces ? 0.3 : 0.15) + 1e-12);
    expectWithinSolidBox(s, V3::Zero(), V3(14, 11, 40) * kVoxel, 0.0);
  }
  EXPECT_GE(whole, 10u);
  EXPECT_LT(parts + 12, strict_parts);
}

TEST(ConvexParts, FaceHoleRuleDoesNotLiftAWallToAClump) {
  // A dense wall 2 cells thick and a clump of 9 voxels (enough for the rule's merge) 4 to 6 cells in
  // front of it: the facets of their union's hull from the clump to the wall's far edges hold no
  // voxel in their middle, so they are no faces, and the clump is not joined to the wall.
  std::vector<V3> c;
  addBox(c, 0, 40, 0, 2, 0, 20);
  addBox(c, 18, 21, 6, 9, 9, 10);
  ConvexPartsParams params;
  params.flat_gap = 0.3;
  const Split s = splitOne(c, params);
  for (const auto& p : s.obstacles[0].parts) {
    const bool wall = p.aabb_min.y() < kVoxel;
    if (wall) {
      EXPECT_LE(p.aabb_max.y(), 2 * kVoxel + 1e-9) << "the wall's hull reaches the clump";
    }
  }
  expectWithinConcavity(c, 0.15, params);
}

/// The stray-part rule's oracle: from the parts made without it, those of at most max_voxels voxels,
/// at most max_core_voxels core, none within reach of a support point, of an obstacle with another
/// part that stays.
std::set<std::size_t> expectedStrays(const Split& plain, const StrayParts& rule, double reach) {
  std::set<std::size_t> out;
  const auto groups = splitConvexParts(plain.centers, kVoxel, {});
  std::vector<std::vector<std::size_t>> stray;
  for (const auto& g : groups) {
    bool drop = g.size() <= rule.max_voxels;
    std::size_t core = 0;
    for (const auto i : g) {
      core += rule.core[i] ? 1 : 0;
      for (const auto& s : rule.support) drop = drop && (plain.centers[i] - s).norm() > reach;
    }
    drop = drop && core <= rule.max_core_voxels;
    if (drop) stray.push_back(g);
  }
  if (groups.size() < 2 || stray.size() == groups.size()) return out;
  for (const auto& g : stray) out.insert(g.begin(), g.end());
  return out;
}

TEST(ConvexParts, StrayPartsDropsOnlySmallBorderPartsOffTheSupport) {
  // A wall 2 m long, 10 cm thick, 1 m high, all core; in front of it (0.4 m and more):
  std::vector<V3> c;
  addBox(c, 0, 40, 0, 2, 0, 20);
  const std::size_t wall = c.size();
  c.push_back(center(20, 8, 15));  // a lone border voxel: dropped
  c.push_back(center(5, 8, 10));   // a pair, both core: kept
  c.push_back(center(6, 8, 10));
  c.push_back(center(32, 8, 1));      // a lone border voxel a voxel above the floor: kept
  addBox(c, 12, 14, 11, 13, 18, 19);  // a clump of 4 border voxels: kept (more than 3)
  StrayParts rule;
  rule.core.assign(c.size(), 0);
  std::fill(rule.core.begin(), rule.core.begin() + std::ptrdiff_t(wall), 1);
  rule.core[wall + 1] = 1;
  rule.core[wall + 2] = 1;
  for (int i = 25; i < 40; ++i) rule.support.push_back(center(i, 8, -1));  // the floor's voxels there
  const Split plain = splitOne(c);
  ASSERT_EQ(plain.obstacles[0].parts.size(), 5u);

  Split s = plain;
  s.obstacles = buildObstacles(c, {}, s.labels, kVoxel);
  s.summary = addConvexParts(s.obstacles, c, {}, s.labels, kVoxel, {}, {}, &rule);
  EXPECT_EQ(s.summary.stray_parts, 1u);
  EXPECT_EQ(s.summary.stray_voxels, std::vector<std::size_t>{wall});
  const auto expected = expectedStrays(plain, rule, 2 * defaultConcavity(kVoxel));
  EXPECT_EQ(std::set<std::size_t>(s.summary.stray_voxels.begin(), s.summary.stray_voxels.end()), expected);
  const Obstacle& o = s.obstacles[0];
  EXPECT_EQ(o.parts.size(), 4u);
  EXPECT_EQ(o.voxel_count, c.size() - 1);
  // The whole obstacle is made again from the voxels it keeps, as buildObstacles makes it.
  std::vector<std::int32_t> kept_labels = s.labels;
  kept_labels[wall] = kNoise;
  const Obstacle again = buildObstacles(c, {}, kept_labels, kVoxel)[0];
  EXPECT_NEAR(o.volume, again.volume, 1e-12);
  EXPECT_TRUE(o.aabb_min.isApprox(again.aabb_min) && o.aabb_max.isApprox(again.aabb_max));
  EXPECT_EQ(o.hull.vertices.size(), again.hull.vertices.size());
  for (const auto& part : o.parts) EXPECT_FALSE(inHull(part.hull, c[wall]));
  EXPECT_NEAR(s.summary.hull_volume_before, o.volume, 1e-12);

  // Not the whole obstacle: two lone border voxels far apart are both its parts, and both stay.
  const std::vector<V3> pair{center(0, 0, 0), center(30, 0, 0)};
  StrayParts loose;
  loose.core.assign(2, 0);
  std::vector<std::int32_t> labels(2, 0);
  auto obstacles = buildObstacles(pair, {}, labels, kVoxel);
  const auto summary = addConvexParts(obstacles, pair, {}, labels, kVoxel, {}, {}, &loose);
  EXPECT_EQ(summary.stray_parts, 0u);
  EXPECT_EQ(obstacles[0].parts.size(), 2u);

  // One core voxel is not enough to stay; none are needed to go with max_core_voxels 0.
  StrayParts one_core = rule;
  one_core.core[wall + 2] = 0;
  Split t = plain;
  t.obstacles = buildObstacles(c, {}, t.labels, kVoxel);
  t.summary = addConvexParts(t.obstacles, c, {}, t.labels, kVoxel, {}, {}, &one_core);
  EXPECT_EQ(t.summary.stray_voxels, (std::vector<std::size_t>{wall, wall + 1, wall + 2}));
  one_core.max_core_voxels = 0;
  t.obstacles = buildObstacles(c, {}, t.labels, kVoxel);
  t.summary = addConvexParts(t.obstacles, c, {}, t.labels, kVoxel, {}, {}, &one_core);
  EXPECT_EQ(t.summary.stray_voxels, std::vector<std::size_t>{wall});

  // A core flag per voxel, or an error.
  loose.core.assign(1, 0);
  EXPECT_THROW(addConvexParts(obstacles, pair, {}, labels, kVoxel, {}, {}, &loose), Error);
}

/// Random stray voxels and clumps around a wall, random core flags and floor: the rule drops exactly
/// the parts its definition names (the oracle re-derives them from the parts made without it).
TEST(ConvexParts, StrayPartsMatchTheirDefinitionOnRandomClutter) {
  std::mt19937 rng(11);
  for (int round = 0; round < 6; ++round) {
    std::vector<V3> c;
    addBox(c, 0, 40, 0, 2, 0, 20);
    std::uniform_int_distribution<int> x(0, 39), y(5, 14), z(0, 19), n(1, 5);
    for (int k = 0; k < 8; ++k) {
      const int i = x(rng), j = y(rng), h = z(rng), m = n(rng);
      addBox(c, i, i + std::min(m, 2), j, j + 1, h, h + (m + 1) / 2);
    }
    StrayParts rule;
    std::bernoulli_distribution core(0.3);
    rule.core.resize(c.size());
    for (auto& f : rule.core) f = core(rng);
    for (int i = 0; i < 40; i += 3) rule.support.push_back(center(i, 6 + round, -1) - V3(0, 0, 0.3 * kVoxel));
    const Split plain = splitOne(c);
    Split s = plain;
    s.obstacles = buildObstacles(c, {}, s.labels, kVoxel);
    s.summary = addConvexParts(s.obstacles, c, {}, s.labels, kVoxel, {}, {}, &rule);
    const auto expected = expectedStrays(plain, rule, 2 * defaultConcavity(kVoxel));
    EXPECT_EQ(std::set<std::size_t>(s.summary.stray_voxels.begin(), s.summary.stray_voxels.end()), expected)
        << "round " << round;
    EXPECT_EQ(s.obstacles[0].voxel_count + s.summary.stray_voxels.size(), c.size());
    std::size_t dropped_parts = plain.obstacles[0].parts.size() - s.obstacles[0].parts.size();
    EXPECT_EQ(s.summary.stray_parts, dropped_parts);
  }
}
TEST(ConvexParts, RingOfWallsBecomesItsWalls) {
  const Split s = splitOne(ring());
  EXPECT_EQ(s.obstacles[0].parts.size(), 4u);
  // The parts swallow little: their hulls are the walls, not the room.
  EXPECT_LT(s.summary.hull_volume_after, 1.2 * s.summary.voxel_volume);
  EXPECT_GT(s.summary.hull_volume_before, 5 * s.summary.voxel_volume);
  expectWithinConcavity(ring(), 0.15);
}

TEST(ConvexParts, LShapeBecomesTwoArms) {
  const Split s = splitOne(lShape());
  EXPECT_EQ(s.obstacles[0].parts.size(), 2u);
  EXPECT_NEAR(s.summary.hull_volume_after, s.summary.voxel_volume, 1e-9);
  expectWithinConcavity(lShape(), 0.15);
}

TEST(ConvexParts, TableIsTopAndLegs) {
  const Split s = splitOne(table());
  EXPECT_GE(s.obstacles[0].parts.size(), 2u);
  EXPECT_LE(s.obstacles[0].parts.size(), 5u);
  expectWithinConcavity(table(), 0.15);
}

TEST(ConvexParts, LargerConcavityKeepsTheL) {
  ConvexPartsParams params;
  params.concavity = 1.0;
  EXPECT_EQ(splitOne(lShape(), params).obstacles[0].parts.size(), 1u);
  expectWithinConcavity(lShape(), 1.0, params);
}

TEST(ConvexParts, RandomBlobsRespectTheBound) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> cell(0, 24);
  for (int trial = 0; trial < 4; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    std::vector<V3> c;
    for (int n = 0; n < 12; ++n) {
      const int i = cell(rng), j = cell(rng), k = cell(rng) / 3;
      addBox(c, i, i + 1 + cell(rng) / 6, j, j + 1 + cell(rng) / 6, k, k + 1 + cell(rng) / 8);
    }
    ConvexPartsParams params;
    params.concavity = 0.1 + 0.05 * trial;
    expectWithinConcavity(c, params.concavity, params);
  }
}

TEST(ConvexParts, TooBigPartsAreCutUnchecked) {
  ConvexPartsParams params;
  params.max_check_cells = 500;  // the box of 20 x 12 x 16 cells is far over
  std::vector<V3> c;
  addBox(c, 0, 20, 0, 12, 0, 16);
  const Split s = splitOne(c, params);
  EXPECT_GT(s.obstacles[0].parts.size(), 1u);
  expectWithinConcavity(c, 0.15, params);
}

TEST(ConvexParts, KeyframeInsideSplits) {
  // Two parallel walls 15 cm apart joined at one end: one part at T = 15 cm (the gap is 3 voxels),
  // but a camera between them must stay outside every hull.
  std::vector<V3> c;
  addBox(c, 0, 30, 0, 2, 0, 10);
  addBox(c, 0, 30, 5, 7, 0, 10);
  addBox(c, 0, 2, 2, 5, 0, 10);
  EXPECT_EQ(splitOne(c).obstacles[0].parts.size(), 1u);
  const std::vector<V3> keyframes{V3(1.0, 0.175, 0.25)};
  const Split s = splitOne(c, {}, KnownFreeSpace{keyframes, {}});
  EXPECT_GT(s.obstacles[0].parts.size(), 1u);
  for (const auto& part : s.obstacles[0].parts) EXPECT_FALSE(inHull(part.hull, keyframes[0]));
  EXPECT_EQ(s.summary.keyframes_in_voxels, 0u);
  expectWithinConcavity(c, 0.15, {}, keyframes);
}

TEST(ConvexParts, KeyframeInAVoxelIsCountedNotSplit) {
  std::vector<V3> c;
  addBox(c, 0, 20, 0, 12, 0, 16);
  const Split s = splitOne(c, {}, KnownFreeSpace{{center(3, 3, 3)}, {}});
  EXPECT_EQ(s.obstacles[0].parts.size(), 1u);
  EXPECT_EQ(s.summary.keyframes_in_voxels, 1u);
}

TEST(ConvexParts, FreeVoxelsInsideHullsAreCounted) {
  // The ring's walls hold no free voxel; the hull of the whole ring holds the room's air.
  KnownFreeSpace known;
  for (int i = 5; i < 35; i += 5)
    for (int j = 5; j < 35; j += 5) known.free_voxels.push_back(center(i, j, 5));  // the room's air
  known.free_voxels.push_back(center(20, 20, 40));                                 // above everything
  const Split s = splitOne(ring(), {}, known);
  EXPECT_EQ(s.summary.free_voxels_inside, 0u);
  ConvexPartsParams whole;
  whole.concavity = 10.0;
  EXPECT_EQ(splitOne(ring(), whole, known).summary.free_voxels_inside, 36u);
  EXPECT_EQ(splitOne(ring(), whole, known).summary.free_voxels_off_surface, 36u);  // all deep in the air
}

// A free voxel counts as off the surface band when none of its part's own voxels is among its 26
// neighbours. Brute force over the voxels, against the parts' counts, on a slab with free voxels in
// front of its face (the band), one voxel further out (inside the hull only when the hull reaches
// there) and deep inside a whole-ring hull.
TEST(ConvexParts, FreeVoxelsOffTheSurfaceBandMatchBruteForce) {
  KnownFreeSpace known;
  for (int i = 0; i < 40; i += 3)
    for (int j = 0; j < 40; j += 3)
      for (int k = -1; k < 22; k += 4) known.free_voxels.push_back(center(i, j, k));
  for (const bool whole_hull : {false, true}) {
    ConvexPartsParams params;
    if (whole_hull) params.concavity = 10.0;
    const Split s = splitOne(ring(), params, known);
    std::size_t inside = 0, off = 0;
    for (const auto& part : s.obstacles[0].parts) {
      inside += part.free_voxels_inside;
      off += part.free_voxels_off_surface;
      EXPECT_LE(part.free_voxels_off_surface, part.free_voxels_inside);
    }
    EXPECT_EQ(s.summary.free_voxels_inside, inside);
    EXPECT_EQ(s.summary.free_voxels_off_surface, off);
    // Brute force: a free voxel in the whole ring's hull (the 2 m square prism of the walls) is off
    // the surface band when no wall voxel lies within one voxel on every axis.
    if (whole_hull) {
      std::size_t expect_inside = 0, expect_off = 0;
      for (const auto& f : known.free_voxels) {
        const V3 c = (f / kVoxel).array() - 0.5;  // lattice cell of the free voxel
        if (c.x() < 0 || c.x() > 39 || c.y() < 0 || c.y() > 39 || c.z() < 0 || c.z() > 19) continue;
        ++expect_inside;
        bool near = false;
        for (const auto& w : s.centers) near = near || ((w - f).cwiseAbs().maxCoeff() <= 1.5 * kVoxel);
        if (!near) ++expect_off;
      }
      EXPECT_EQ(s.summary.free_voxels_inside, expect_inside);
      EXPECT_EQ(s.summary.free_voxels_off_surface, expect_off);
      EXPECT_GT(expect_inside, expect_off);  // the test holds free voxels in the band too
      EXPECT_GT(expect_off, 0u);
    }
  }
}

TEST(ConvexParts, DeterministicAndThreadCountIndependent) {
  std::vector<V3> centers;
  std::vector<std::int32_t> labels;
  const std::vector<std::vector<V3>> shapes{ring(), lShape(), table()};
  for (std::size_t s = 0; s < shapes.size(); ++s)
    for (const auto& c : shapes[s]) {
      centers.push_back(c + V3(5.0 * double(s), 0, 0));
      labels.push_back(std::int32_t(s));
    }
  const auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    auto obstacles = buildObstacles(centers, {}, labels, kVoxel);
    addConvexParts(obstacles, centers, {}, labels, kVoxel, {});
    return obstacles;
  };
  const auto a = run(1), b = run(4), c = run(4);
  ASSERT_EQ(a.size(), 3u);
  for (const auto* other : {&b, &c}) {
    ASSERT_EQ(other->size(), a.size());
    for (std::size_t o = 0; o < a.size(); ++o) {
      ASSERT_EQ((*other)[o].parts.size(), a[o].parts.size());
      for (std::size_t p = 0; p < a[o].parts.size(); ++p) {
        EXPECT_EQ((*other)[o].parts[p].hull.vertices, a[o].parts[p].hull.vertices);
        EXPECT_EQ((*other)[o].parts[p].hull.triangles, a[o].parts[p].hull.triangles);
      }
    }
  }
}

TEST(ConvexParts, BadInputThrowsNamingTheParameter) {
  const std::vector<V3> c{center(0, 0, 0)};
  ConvexPartsParams bad;
  bad.concavity = -1;
  EXPECT_THROW(splitConvexParts(c, kVoxel, bad), Error);
  EXPECT_THROW(splitConvexParts(c, 0.0, {}), Error);
  try {
    splitConvexParts(c, kVoxel, bad);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("concavity"), std::string::npos);
  }
  std::vector<Obstacle> none;
  EXPECT_THROW(addConvexParts(none, c, {}, {0, 0}, kVoxel, {}), Error);
  for (const double g : {-0.1, std::nan(""), std::numeric_limits<double>::infinity()}) {
    ConvexPartsParams bad_gap;
    bad_gap.flat_gap = g;
    try {
      splitConvexParts(c, kVoxel, bad_gap);
      ADD_FAILURE() << "flat_gap " << g << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("flat_gap"), std::string::npos) << e.what();
    }
  }
}

/// A real ORB-SLAM map built as `hullmap build MAP --up -y --eps 0.2 --min-pts 3` would, with its
/// voxel centres and weights.
struct RealMap {
  hullmap::pipeline::BuildResult result;
  std::vector<V3> centers;
  std::vector<std::uint32_t> weights;
};

RealMap buildRealMap(const std::string& path) {
  hullmap::pipeline::BuildParams params;
  params.inputs = {path};
  params.frame.up = hullmap::mapper::parseUpAxis("-y");
  params.eps = 0.2;
  params.min_pts = 3;
  params.floor.mode = hullmap::mapper::PlaneSetting::Mode::kNone;  // whole clusters, split below
  params.convex_parts.reset();
  RealMap real{hullmap::pipeline::build(params), {}, {}};
  for (const auto& v : real.result.voxels) {
    real.centers.push_back(v.center);
    real.weights.push_back(v.weight);
  }
  return real;
}

TEST(ConvexParts, RealMH01MapSplitsItsOneBigCluster) {
  // The real ORB-SLAM3 MH_01 map (25,889 points, mostly ground) at eps 0.2 / minPts 3: one cluster
  // covers most of the map. Prints size, parts and time.
  HULLMAP_REQUIRE_REAL_DATA(path, "orbslam3_euroc_MH_01_mono_pointcloud.txt");
  RealMap real = buildRealMap(path);
  hullmap::pipeline::BuildResult& r = real.result;
  const std::vector<V3>& centers = real.centers;
  const std::vector<std::uint32_t>& weights = real.weights;
  const auto start = std::chrono::steady_clock::now();
  const ConvexPartsSummary summary =
      addConvexParts(r.obstacles, centers, weights, r.clusters.labels, r.map.resolution(), ConvexPartsParams{});
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::size_t largest = 0, clustered = 0;
  for (const auto& o : r.obstacles) {
    largest = std::max(largest, o.voxel_count);
    clustered += o.voxel_count;
  }
  std::cout << "MH_01 eps 0.2 minPts 3: " << centers.size() << " voxels, " << clustered << " clustered in "
            << r.obstacles.size() << " obstacles (largest " << largest << ") -> " << summary.parts << " parts in " << ms
            << " ms; hull volume " << summary.hull_volume_before << " -> " << summary.hull_volume_after
            << ", voxel volume " << summary.voxel_volume << "\n";
  for (const auto& o : r.obstacles)
    for (const auto& part : o.parts) EXPECT_LE(part.concavity_bound, summary.concavity + 1e-12);
  EXPECT_LT(summary.hull_volume_after, 0.5 * summary.hull_volume_before);
}

TEST(ConvexParts, RealV101MapRespectsTheBound) {
  // The real ORB-SLAM2 V1_01 map at 5 cm, clustered at eps 0.2 / minPts 3 (the room's structure
  // becomes one ring-shaped cluster). Prints the numbers the issue asks for (time is not asserted).
  HULLMAP_REQUIRE_REAL_DATA(path, "orbslam2_euroc_V1_01_MapPoints.txt");
  RealMap real = buildRealMap(path);
  hullmap::pipeline::BuildResult& r = real.result;
  const std::vector<V3>& centers = real.centers;
  const std::vector<std::uint32_t>& weights = real.weights;
  const double size = r.map.resolution();
  ASSERT_EQ(size, kVoxel);  // distanceToCubes assumes it
  const auto start = std::chrono::steady_clock::now();
  const ConvexPartsSummary summary =
      addConvexParts(r.obstacles, centers, weights, r.clusters.labels, size, ConvexPartsParams{});
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::size_t clustered = 0;
  for (const auto& o : r.obstacles) clustered += o.voxel_count;
  std::cout << "V1_01 eps 0.2 minPts 3: " << centers.size() << " voxels, " << clustered << " clustered in "
            << r.obstacles.size() << " obstacles -> " << summary.parts << " parts in " << ms << " ms; hull volume "
            << summary.hull_volume_before << " -> " << summary.hull_volume_after << " m^3, voxel volume "
            << summary.voxel_volume << " m^3\n";
  EXPECT_GT(summary.parts, r.obstacles.size());
  EXPECT_LT(summary.hull_volume_after, 0.5 * summary.hull_volume_before);
  // The oracle on the biggest obstacle's parts.
  const auto biggest = std::max_element(r.obstacles.begin(), r.obstacles.end(),
                                        [](const auto& a, const auto& b) { return a.voxel_count < b.voxel_count; });
  std::vector<V3> cluster;
  for (std::size_t i = 0; i < centers.size(); ++i)
    if (r.clusters.labels[i] == biggest->id) cluster.push_back(centers[i]);
  const auto groups = splitConvexParts(cluster, size, {});
  ASSERT_EQ(groups.size(), biggest->parts.size());
  std::mt19937 rng(11);
  for (std::size_t p = 0; p < groups.size(); ++p) {
    if (biggest->parts[p].filled) continue;  // its bound counts the space its cluster encloses
    std::vector<V3> own;
    for (const auto i : groups[p]) own.push_back(cluster[i]);
    double worst = 0.0;
    for (const auto& x : sampleHull(biggest->parts[p].hull, 100, rng)) worst = std::max(worst, distanceToCubes(x, own));
    EXPECT_LE(worst, defaultConcavity(size) + 1e-9) << "part " << p;
  }
}

}  // namespace
}  // namespace hullmap::hulls
