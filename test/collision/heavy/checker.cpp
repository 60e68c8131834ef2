// Path checks: HullChecker against the exact oracle over every obstacle; batch = one by one;
// paths; octree mode consistent with hull mode (a clustered voxel the octree finds, the hulls find).
#include <gtest/gtest.h>

#include <octomap/OcTree.h>

#include <fcl/geometry/shape/sphere.h>

#include "checker_fixtures.hpp"
#include "collision_oracle.hpp"
#include "hullmap/collision/fcl_obstacles.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::collision {
namespace {

TEST(HullChecker, MatchesOracleOverAllObstacles) {
  const Scene scene = randomScene(21, 25, 0.1);
  const HullChecker checker(scene.obstacles);
  std::mt19937 rng(5);
  int colliding = 0, clear = 0;
  for (int i = 0; i < 1500; ++i) {
    const Segment s = randomSegment(rng, 3.0, i % 7 == 0 ? 0.0 : 2.0);
    const double r = 0.1 * (i % 4);
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& o : scene.obstacles)
      if (test::boxGap(s.a, s.b, o.hull) < nearest) nearest = std::min(nearest, test::segmentHull(s.a, s.b, o.hull));
    if (std::abs(nearest - r) < 1e-8) continue;  // grazing within the oracle's own precision
    const SegmentCheck c = checker.check(s, r);
    ASSERT_EQ(c.collides, nearest <= r) << "segment " << i << " nearest " << nearest << " r " << r;
    if (!c.collides) {
      ++clear;
      EXPECT_EQ(c.obstacle, -1);
      EXPECT_NEAR(c.clearance, nearest - r, 1e-9);
      continue;
    }
    ++colliding;
    EXPECT_EQ(c.clearance, 0.0);
    ASSERT_GE(c.obstacle, 0);
    const double length = (s.b - s.a).norm();
    const double tol = length > 0 ? std::max(1e-3, 1e-3 / length) : 1.0;
    const V3 contact = s.a + c.t * (s.b - s.a);
    // The reported obstacle is touched by the sweep up to t, and nothing is touched before t - tol.
    EXPECT_LE(test::segmentHull(s.a, contact, scene.obstacles[std::size_t(c.obstacle)].hull), r + 1e-9);
    if (c.t > tol) {
      const V3 before = s.a + (c.t - tol) * (s.b - s.a);
      for (const auto& o : scene.obstacles) {
        if (test::boxGap(s.a, before, o.hull) <= r) {
          EXPECT_GT(test::segmentHull(s.a, before, o.hull), r - 1e-9);
        }
      }
    }
  }
  EXPECT_GT(colliding, 100);
  EXPECT_GT(clear, 100);
}

/// Octree mode against hull mode: whenever the capsule touches a clustered voxel (exact oracle),
/// both modes must report a collision; and every octree hit on a clustered voxel is a hull hit.
TEST(OctreeChecker, ClusteredVoxelHitsAreHullHits) {
  const double size = 0.1;
  Scene scene = randomScene(24, 20, size);
  std::mt19937 rng(8);
  octomap::OcTree tree(size);
  std::vector<V3> noise;
  for (int i = 0; i < 200; ++i) {
    const V3 c = V3(int(rng() % 60) - 30 + 0.5, int(rng() % 60) - 30 + 0.5, int(rng() % 30) + 0.5) * size;
    noise.push_back(c);
  }
  for (const auto& c : scene.voxels.centers)
    tree.updateNode(octomap::point3d(float(c.x()), float(c.y()), float(c.z())), true);
  for (const auto& c : noise) tree.updateNode(octomap::point3d(float(c.x()), float(c.y()), float(c.z())), true);
  const OctreeChecker octree(tree);
  const HullChecker hulls(scene.obstacles);

  // Exact segment-to-voxel-box distance, nearest over a set of voxels.
  auto nearestVoxel = [&](const Segment& s, const std::vector<V3>& centers) {
    double best = std::numeric_limits<double>::infinity();
    const V3 half = V3::Constant(size / 2);
    for (const auto& c : centers) best = std::min(best, test::segmentBox(s.a, s.b, c - half, c + half));
    return best;
  };

  int octree_hits_on_clusters = 0, octree_hits = 0;
  for (int i = 0; i < 400; ++i) {
    const Segment s = randomSegment(rng, 3.0, 1.5);
    const double r = 0.05 + 0.05 * (i % 3);
    const auto o = octree.check(s, r);
    const auto h = hulls.check(s, r);
    const double to_cluster = nearestVoxel(s, scene.voxels.centers);
    const double to_noise = nearestVoxel(s, noise);
    octree_hits += o.collides;
    if (to_cluster < r - 1e-6) {
      EXPECT_TRUE(o.collides) << "octree mode misses a clustered voxel, segment " << i;
      EXPECT_TRUE(h.collides) << "hull mode misses a clustered voxel, segment " << i;
    }
    if (o.collides && to_noise > r + 1e-6) {
      // The octree's hit can only be a clustered voxel: the hulls must see it too, no later.
      ++octree_hits_on_clusters;
      EXPECT_TRUE(h.collides) << "segment " << i;
      const double tol = std::max(1e-3, 1e-3 / (s.b - s.a).norm());
      if (h.collides) {
        EXPECT_LE(h.t, o.t + tol);
      }
    }
    if (!o.collides) {
      EXPECT_GT(std::min(to_cluster, to_noise), r - 1e-6) << "segment " << i;
      EXPECT_NEAR(o.clearance, std::min(to_cluster, to_noise) - r, 1e-3);
    }
  }
  EXPECT_GT(octree_hits_on_clusters, 20);
  EXPECT_GT(octree_hits, octree_hits_on_clusters);
}

}  // namespace
}  // namespace hullmap::collision
