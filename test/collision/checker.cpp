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

// A planner's own FCL query names the obstacle it met by the obstacle's id, as HullChecker does.
TEST(FclObstacles, CallbacksNameTheObstacleByItsId) {
  std::vector<V3> centers;
  std::vector<std::int32_t> labels;
  for (int i = 0; i < 4; ++i) {
    centers.emplace_back(0.1 * i, 0.0, 1.0);
    labels.push_back(0);
    centers.emplace_back(5.0 + 0.1 * i, 0.0, 1.0);
    labels.push_back(1);
  }
  auto obstacles = hulls::buildObstacles(centers, std::vector<std::uint32_t>(centers.size(), 1), labels, 0.1);
  ASSERT_EQ(obstacles.size(), 2u);
  obstacles[0].id = 7;
  obstacles[1].id = 3;
  const FclObstacles fcl(obstacles);
  fcl::CollisionObjectd sphere(std::make_shared<fcl::Sphered>(0.1), fcl::Transform3d(Eigen::Translation3d(5.1, 0, 1)));
  struct Query {
    const FclObstacles* fcl;
    const fcl::CollisionObjectd* sphere;
    std::vector<int> ids;
  } query{&fcl, &sphere, {}};
  fcl.manager().collide(&sphere, &query, [](fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* data) {
    auto* q = static_cast<Query*>(data);
    q->ids.push_back(q->fcl->idOf(a == q->sphere ? *b : *a));
    return false;
  });
  EXPECT_EQ(query.ids, std::vector<int>{3});
  const HullChecker checker(obstacles);
  EXPECT_EQ(checker.check({V3(5.1, -1, 1), V3(5.1, 1, 1)}, 0.1).obstacle, 3);
}

TEST(HullChecker, BatchEqualsOneByOneAndPathsReportFirstContact) {
  const Scene scene = randomScene(22, 30, 0.1);
  const HullChecker checker(scene.obstacles);
  std::mt19937 rng(6);
  std::vector<Segment> segments;
  for (int i = 0; i < 3000; ++i) segments.push_back(randomSegment(rng, 3.0, 1.5));
  const auto batch = checker.checkBatch(segments, 0.2);
  ASSERT_EQ(batch.size(), segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const auto one = checker.check(segments[i], 0.2);
    EXPECT_EQ(batch[i].collides, one.collides);
    EXPECT_EQ(batch[i].obstacle, one.obstacle);
    EXPECT_EQ(batch[i].t, one.t);
    EXPECT_EQ(batch[i].clearance, one.clearance);
  }
  int paths_hit = 0;
  for (int p = 0; p < 100; ++p) {
    std::vector<V3> waypoints{randomSegment(rng, 3.0, 0).a};
    for (int k = 0; k < 6; ++k) waypoints.push_back(waypoints.back() + randomSegment(rng, 1.0, 1.0).b * 0.5);
    const PathCheck path = checker.checkPath(waypoints, 0.15);
    ASSERT_EQ(path.segments.size(), waypoints.size() - 1);
    std::optional<std::size_t> first;
    for (std::size_t k = 0; k < path.segments.size() && !first; ++k)
      if (checker.check({waypoints[k], waypoints[k + 1]}, 0.15).collides) first = k;
    EXPECT_EQ(path.first_colliding_segment, first);
    if (first) {
      ++paths_hit;
      ASSERT_TRUE(path.first_contact.has_value());
      const auto& a = waypoints[*first];
      const auto& b = waypoints[*first + 1];
      EXPECT_TRUE(path.first_contact->isApprox(a + path.segments[*first].t * (b - a)));
    } else {
      EXPECT_FALSE(path.first_contact.has_value());
    }
  }
  EXPECT_GT(paths_hit, 10);
}

TEST(HullChecker, NoObstaclesNothingCollidesAndBadInputThrows) {
  const HullChecker empty({});
  const auto c = empty.check({V3::Zero(), V3::Ones()}, 0.3);
  EXPECT_FALSE(c.collides);
  EXPECT_EQ(c.obstacle, -1);
  const Scene scene = randomScene(23, 3, 0.1);
  const HullChecker checker(scene.obstacles);
  EXPECT_THROW(checker.check({V3::Zero(), V3::Ones()}, -1.0), Error);
  EXPECT_THROW(checker.check({V3::Zero(), V3::Constant(std::nan(""))}, 0.1), Error);
}

}  // namespace
}  // namespace hullmap::collision
