// HullChecker with convex parts: one FCL object per part, answers name the obstacle and the part;
// the free notch of an L is free with parts and blocked by the whole hull.
#include <gtest/gtest.h>

#include "hullmap/collision/fcl_obstacles.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"

namespace hullmap::collision {
namespace {

using V3 = Eigen::Vector3d;

/// An L of 5 cm voxels: arm along x [0, 1.5] x [0, 0.2], arm along y [0, 0.2] x [0, 1], 0.5 high;
/// obstacle id 7.
std::vector<hulls::Obstacle> lShape(bool with_parts) {
  std::vector<V3> centers;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 20; ++j)
      for (int k = 0; k < 10; ++k)
        if (j < 4 || i < 4) centers.push_back(V3(i + 0.5, j + 0.5, k + 0.5) * 0.05);
  const std::vector<std::int32_t> labels(centers.size(), 7);
  auto obstacles = hulls::buildObstacles(centers, {}, labels, 0.05);
  if (with_parts) hulls::addConvexParts(obstacles, centers, {}, labels, 0.05, {});
  return obstacles;
}

TEST(HullCheckerParts, OneObjectPerPart) {
  const auto obstacles = lShape(true);
  ASSERT_EQ(obstacles.size(), 1u);
  ASSERT_EQ(obstacles[0].parts.size(), 2u);
  const FclObstacles fcl(obstacles);
  ASSERT_EQ(fcl.size(), 2u);
  for (std::size_t i = 0; i < fcl.size(); ++i) {
    EXPECT_EQ(fcl.source(i).id, 7);
    EXPECT_EQ(fcl.source(i).part, int(i));
    EXPECT_EQ(FclObstacles::indexOf(fcl.object(i)), i);
  }
  EXPECT_EQ(FclObstacles(lShape(false)).source(0).part, -1);
}

TEST(HullCheckerParts, TheNotchIsFreeWithParts) {
  // Vertical segment in the L's notch at (0.8, 0.6): 0.4 m from both arms, inside the whole hull.
  const Segment notch{V3(0.8, 0.6, 0.1), V3(0.8, 0.6, 0.4)};
  const SegmentCheck whole = HullChecker(lShape(false)).check(notch, 0.1);
  EXPECT_TRUE(whole.collides);
  EXPECT_EQ(whole.obstacle, 7);
  EXPECT_EQ(whole.part, -1);
  const SegmentCheck parts = HullChecker(lShape(true)).check(notch, 0.1);
  EXPECT_FALSE(parts.collides);
  // Clearance to the nearer arm: the x arm ends at y = 0.2, the y arm at x = 0.2.
  EXPECT_NEAR(parts.clearance, 0.4 - 0.1, 1e-9);
}

TEST(HullCheckerParts, AnswersNameTheObstacleAndPart) {
  const auto obstacles = lShape(true);
  const HullChecker checker(obstacles);
  // Into the x arm's far end, and into the y arm's far end, from outside.
  const SegmentCheck x_arm = checker.check({V3(1.4, 0.6, 0.25), V3(1.4, 0.1, 0.25)}, 0.05);
  const SegmentCheck y_arm = checker.check({V3(0.6, 0.9, 0.25), V3(0.1, 0.9, 0.25)}, 0.05);
  ASSERT_TRUE(x_arm.collides);
  ASSERT_TRUE(y_arm.collides);
  EXPECT_EQ(x_arm.obstacle, 7);
  EXPECT_EQ(y_arm.obstacle, 7);
  ASSERT_NE(x_arm.part, y_arm.part);
  const auto& hit_x = obstacles[0].parts[std::size_t(x_arm.part)];
  const auto& hit_y = obstacles[0].parts[std::size_t(y_arm.part)];
  EXPECT_GT(hit_x.aabb_max.x(), 1.0);  // the x arm
  EXPECT_GT(hit_y.aabb_max.y(), 0.9);  // the y arm
  // First contact where the capsule reaches y = 0.25 (x arm) and x = 0.25 (y arm), bracketed within
  // the checker's tolerance (1e-3 / length = 2e-3 of the segment).
  EXPECT_NEAR(x_arm.t, (0.6 - 0.25) / 0.5, 2e-3);
  EXPECT_NEAR(y_arm.t, (0.6 - 0.25) / 0.5, 2e-3);
}

}  // namespace
}  // namespace hullmap::collision
