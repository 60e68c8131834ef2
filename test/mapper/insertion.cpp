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

// Voxels of a few bricks marked free and occupied by a pattern, in `threads` BrickSets (a voxel
// in one or several of them), applied as one scan update `repeats` times against octomap's
// updateNode for each free-only voxel, then each occupied one (insertPointCloud's order).
void expectBrickPatternAsUpdateNode(int (*pattern)(int x, int y, int z, std::mt19937_64& rng), int threads,
                                    int repeats) {
  std::mt19937_64 rng(11);
  // Bricks in several octants of the root, and a 2x2x2 group of bricks under one depth-12 node.
  const int corners[][3] = {{32768, 32768, 32768}, {32760, 32768, 32752}, {32776, 32760, 32768},
                            {40000, 20000, 32768}, {32784, 32784, 32784}, {32792, 32784, 32784},
                            {32784, 32792, 32784}, {32784, 32784, 32792}, {32792, 32792, 32792}};
  std::vector<detail::BrickSet> sets(threads);
  octomap::KeySet free_keys, occupied_keys;
  for (const auto& c : corners) {
    for (int z = 0; z < 8; ++z) {
      for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) {
          const int kind = pattern(x, y, z, rng);  // 0 none, 1 free, 2 occupied, 3 both
          if (kind == 0) continue;
          const int key[3] = {c[0] + x, c[1] + y, c[2] + z};
          const octomap::OcTreeKey k(static_cast<octomap::key_type>(key[0]), static_cast<octomap::key_type>(key[1]),
                                     static_cast<octomap::key_type>(key[2]));
          if (kind & 1) sets[rng() % threads].mark(key, false);
          if (kind & 2) sets[rng() % threads].mark(key, true);
          (kind & 2 ? occupied_keys : free_keys).insert(k);
        }
      }
    }
  }
  const detail::ScanUpdate update(sets);
  octomap::OcTree expected(0.1), actual(0.1);
  for (int r = 0; r < repeats; ++r) {
    for (const auto& k : free_keys) expected.updateNode(k, false);
    for (const auto& k : occupied_keys) expected.updateNode(k, true);
    detail::applyScanUpdate(actual, update);
    ASSERT_TRUE(sameTree(expected, actual)) << "threads " << threads << ", application " << r + 1;
  }
}

TEST(MapperInsertion, BrickUpdateIsUpdateNodePerVoxel) {
  // Whole bricks, 4x4x4 words and 2x2x2 blocks of one kind (a new node collapses into one leaf),
  // kinds that vary inside every word alike (x % 4: the same bits occupied in all 8 words), and
  // random mixes; repeated until the leaves clamp and prune.
  const auto all_free = [](int, int, int, std::mt19937_64&) { return 1; };
  const auto all_occupied = [](int, int, int, std::mt19937_64&) { return 2; };
  const auto planes = [](int x, int, int, std::mt19937_64&) { return x % 4 == 0 ? 2 : 1; };
  const auto one_word = [](int x, int y, int z, std::mt19937_64&) { return x < 4 && y < 4 && z >= 4 ? 3 : 1; };
  const auto blocks = [](int x, int y, int z, std::mt19937_64&) { return (x / 2 + y / 2 + z / 2) % 3; };
  const auto mixed = [](int, int, int, std::mt19937_64& rng) { return static_cast<int>(rng() % 4); };
  for (auto pattern : {+all_free, +all_occupied, +planes, +one_word, +blocks, +mixed}) {
    for (int threads : {1, 3}) expectBrickPatternAsUpdateNode(pattern, threads, 6);
  }
}

TEST(MapperInsertion, PointsInOneVoxelAndOriginInsideTheCloud) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  Points points;
  // Clusters of points sharing voxels, the origin among them, and points at the origin itself.
  for (int c = 0; c < 50; ++c) {
    const Point centre(0.3 * (c % 7) - 1.0, 0.2 * (c / 7) - 0.7, 0.05 * c - 1.2);
    for (int i = 0; i < 40; ++i) points.push_back(centre + Point(u(rng), u(rng), u(rng)));
  }
  points.push_back(Point(0.01, 0.01, 0.01));
  points.push_back(Point::Zero());
  for (double resolution : {0.05, 0.1}) {
    expectSameAsOctomap(points, Point(0.01, 0.02, 0.03), resolution, -1.0, 3);
    expectSameAsOctomap(points, Point(0.01, 0.02, 0.03), resolution, 0.8, 2);
  }
}

TEST(MapperInsertion, UnaddressablePointsAreSkippedAsOctomapDoes) {
  // At 0.01 m octomap addresses +-327 m: these far points have no key; with a max_range their
  // shortened rays still clear free space, as in insertPointCloud.
  Points points = {Point(1.0, 2.0, 0.5), Point(400.0, 0.0, 0.0), Point(0.0, -1e6, 3.0), Point(-2.0, 0.5, 0.2)};
  expectSameAsOctomap(points, Point::Zero(), 0.01, -1.0, 1);
  expectSameAsOctomap(points, Point::Zero(), 0.01, 3.0, 2);
  // Origin outside the tree: no free space, only the addressable endpoints.
  expectSameAsOctomap(points, Point(1000.0, 0.0, 0.0), 0.01, -1.0, 1);
}

TEST(MapperInsertion, EmptyScanLeavesTheTreeAlone) {
  octomap::OcTree tree(0.1);
  insertScan(tree, {}, Point::Zero(), -1.0);
  EXPECT_EQ(tree.size(), 0u);
  insertScan(tree, {Point(1, 0, 0)}, Point::Zero(), -1.0);
  const std::size_t size = tree.size();
  insertScan(tree, {}, Point::Zero(), -1.0);
  EXPECT_EQ(tree.size(), size);
  EXPECT_GT(size, 0u);
}

}  // namespace
}  // namespace hullmap::mapper
