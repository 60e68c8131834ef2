// Surfaces as obstacles: a capsule against a solid half-space, exactly (oracle: the distance to a
// half-space is linear along the segment; the first contact by bisection on that exact test), every
// segment through a floor collides at any radius, and hulls and surfaces together in both checkers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <octomap/OcTree.h>

#include "collision_oracle.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"

namespace hullmap::collision {
namespace {

using test::V3;

Surface randomSurface(std::mt19937& rng, const char* name) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const V3 normal = V3(n(rng), n(rng), n(rng)).normalized();
  return Surface::plane(name, normal, u(rng));
}

/// Whether the sphere of `radius` swept from a to a + t (b - a) meets the solid: the least signed
/// distance over the prefix is at one of its ends.
bool prefixTouches(const Segment& s, double t, double radius, const Surface& h) {
  return std::min(h.distance(s.a), h.distance(s.a + t * (s.b - s.a))) <= radius;
}

TEST(SurfaceCheck, CapsuleAgainstASurfaceMatchesTheOracle) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coordinate(-4.0, 4.0), radius(0.0, 1.5);
  int collisions = 0, clear = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const Surface h = randomSurface(rng, "floor");
    const Segment s{V3(coordinate(rng), coordinate(rng), coordinate(rng)),
                    V3(coordinate(rng), coordinate(rng), coordinate(rng))};
    const double r = trial % 10 == 0 ? 0.0 : radius(rng);
    const SegmentCheck c = checkSurface(s, r, h);
    const bool touches = prefixTouches(s, 1.0, r, h);
    ASSERT_EQ(c.collides, touches) << "trial " << trial;
    if (!c.collides) {
      ++clear;
      EXPECT_NEAR(c.clearance, std::min(h.distance(s.a), h.distance(s.b)) - r, 1e-12);
      EXPECT_TRUE(c.surface.empty());
      continue;
    }
    ++collisions;
    EXPECT_EQ(c.surface, "floor");
    EXPECT_EQ(c.clearance, 0.0);
    EXPECT_EQ(c.obstacle, -1);
    // The oracle's first contact: bisection on the exact prefix test.
    double lo = 0.0, hi = 1.0;
    if (prefixTouches(s, 0.0, r, h)) hi = 0.0;
    while (hi - lo > 1e-13) {
      const double mid = 0.5 * (lo + hi);
      (prefixTouches(s, mid, r, h) ? hi : lo) = mid;
    }
    EXPECT_NEAR(c.t, hi, 1e-9) << "trial " << trial;
  }
  EXPECT_GT(collisions, 1000);
  EXPECT_GT(clear, 1000);
}

TEST(SurfaceCheck, EverySegmentThroughTheFloorCollidesAtAnyRadius) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> xy(-10.0, 10.0), height(0.0, 5.0), radius(0.0, 2.0);
  const Surface floor = Surface::plane("floor", V3(0.02, -0.01, 1.0).normalized(), 0.05);
  const std::vector<hulls::Obstacle> none;
  const HullChecker hulls(none, {floor});
  for (int trial = 0; trial < 2000; ++trial) {
    // One end above the floor's plane, the other below it.
    V3 above(xy(rng), xy(rng), 0.0), below(xy(rng), xy(rng), 0.0);
    above.z() = (floor.offset - floor.normal.x() * above.x() - floor.normal.y() * above.y()) / floor.normal.z() +
                height(rng) + 1e-9;
    below.z() = (floor.offset - floor.normal.x() * below.x() - floor.normal.y() * below.y()) / floor.normal.z() -
                height(rng) - 1e-9;
    const double r = trial % 4 == 0 ? 0.0 : radius(rng);
    const Segment s = trial % 2 ? Segment{above, below} : Segment{below, above};
    const SegmentCheck c = hulls.check(s, r);
    ASSERT_TRUE(c.collides) << "trial " << trial << " radius " << r;
    EXPECT_EQ(c.surface, "floor");
    if (trial % 2 == 0) {
      EXPECT_EQ(c.t, 0.0);  // it starts under the floor
    }
  }
}

TEST(SurfaceCheck, TheEarliestOfHullsAndSurfacesIsReported) {
  // A 1 m box standing on a floor at z = 0 (voxels 0..1 m, 0.1 m each).
  std::vector<V3> centers;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) centers.emplace_back(0.05 + 0.1 * i, 0.05 + 0.1 * j, 0.05 + 0.1 * k);
  auto obstacles = hulls::buildObstacles(centers, std::vector<std::uint32_t>(centers.size(), 1),
                                         std::vector<std::int32_t>(centers.size(), 0), 0.1);
  obstacles[0].id = 4;
  const Surface floor = Surface::plane("floor", V3::UnitZ(), 0.0);
  const Surface ceiling = Surface::plane("ceiling", -V3::UnitZ(), -3.0);
  const HullChecker checker(obstacles, {floor, ceiling});
  ASSERT_EQ(checker.surfaces().size(), 2u);

  // Horizontal at z = 0.5 into the box: the box first.
  SegmentCheck c = checker.check({V3(-2, 0.5, 0.5), V3(3, 0.5, 0.5)}, 0.2);
  EXPECT_TRUE(c.collides);
  EXPECT_EQ(c.obstacle, 4);
  EXPECT_TRUE(c.surface.empty());
  EXPECT_NEAR(c.t, 1.8 / 5.0, 2e-3);
  // Down into the floor beside the box: the floor, at z = 0.2.
  c = checker.check({V3(-1, 0.5, 2), V3(-1, 0.5, -1)}, 0.2);
  EXPECT_EQ(c.surface, "floor");
  EXPECT_EQ(c.obstacle, -1);
  EXPECT_EQ(c.part, -1);
  EXPECT_NEAR(c.t, 1.8 / 3.0, 1e-12);
  // Down onto the box's top: the box first (z = 1.2), then the floor.
  c = checker.check({V3(0.5, 0.5, 2.5), V3(0.5, 0.5, -1)}, 0.2);
  EXPECT_EQ(c.obstacle, 4);
  EXPECT_NEAR(c.t, 1.3 / 3.5, 2e-3);
  // Up into the ceiling.
  c = checker.check({V3(-1, -1, 2), V3(-1, -1, 3.5)}, 0.1);
  EXPECT_EQ(c.surface, "ceiling");
  EXPECT_NEAR(c.t, 0.9 / 1.5, 1e-12);
  // Clear: the clearance is the least of the box's and the surfaces'.
  c = checker.check({V3(-1, -1, 2.5), V3(-0.5, -1, 2.5)}, 0.1);
  EXPECT_FALSE(c.collides);
  EXPECT_NEAR(c.clearance, 0.4, 1e-9);  // the ceiling, 0.5 above, less the radius
  c = checker.check({V3(-1, -1, 1.5), V3(-0.5, -1, 1.5)}, 0.1);
  EXPECT_NEAR(c.clearance, std::sqrt(1.0 + 0.25 + 0.25) - 0.1, 1e-6);  // the box's corner edge (0, 0, 1)

  // A path: the first colliding segment and its contact point on it.
  const PathCheck path = checker.checkPath({V3(-1, -1, 2), V3(-1, -1, 1), V3(-1, -1, -1)}, 0.25);
  ASSERT_TRUE(path.first_colliding_segment);
  EXPECT_EQ(*path.first_colliding_segment, 1u);
  EXPECT_EQ(path.segments[1].surface, "floor");
  EXPECT_NEAR(path.first_contact->z(), 0.25, 1e-12);
}

TEST(SurfaceCheck, OctreeModeSeesTheFloorBetweenItsSparseVoxels) {
  // A sparse floor: voxels every 0.5 m; a thin vertical sweep between them passes the voxels.
  octomap::OcTree tree(0.1);
  for (double x = 0.05; x < 3; x += 0.5)
    for (double y = 0.05; y < 3; y += 0.5) tree.updateNode(octomap::point3d(float(x), float(y), 0.05f), true);
  tree.updateNode(octomap::point3d(1.05f, 0.05f, 1.05f), true);  // one voxel in the air
  const Segment down{V3(0.3, 0.3, 2), V3(0.3, 0.3, -1)};
  EXPECT_FALSE(OctreeChecker(tree).check(down, 0.05).collides);
  const OctreeChecker checker(tree, {Surface::plane("floor", V3::UnitZ(), 0.1)});
  const SegmentCheck c = checker.check(down, 0.05);
  EXPECT_TRUE(c.collides);
  EXPECT_EQ(c.surface, "floor");
  EXPECT_NEAR(c.t, (2 - 0.15) / 3.0, 1e-12);
  // A voxel hit is a voxel hit.
  const SegmentCheck v = checker.check({V3(0, 0.05, 1.05), V3(2, 0.05, 1.05)}, 0.01);
  EXPECT_TRUE(v.collides);
  EXPECT_TRUE(v.surface.empty());
  EXPECT_NEAR(v.t, 0.495, 2e-3);
}

TEST(SurfaceCheck, BadSurfacesAreRefusedNamingThem) {
  const std::vector<hulls::Obstacle> none;
  for (const Surface& bad : {Surface::plane("floor", V3(0, 0, 2), 0.0), Surface::plane("floor", V3(0, 0, NAN), 0.0),
                             Surface::plane("floor", V3::UnitZ(), INFINITY)}) {
    try {
      HullChecker checker(none, {bad});
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.parameter(), "surfaces") << e.what();
      EXPECT_NE(std::string(e.what()).find("\"floor\""), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(checkSurface({V3::Zero(), V3::Ones()}, -1.0, Surface::plane("floor", V3::UnitZ(), 0.0)), Error);
}

}  // namespace
}  // namespace hullmap::collision
