// planPathOmpl: RRT* with hullmap's exact capsule sweep as motion validator. Paths are judged by a
// brute-force oracle (dense samples against the true boxes), not by the checker they were made with.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/planning/ompl_planner.hpp"
#include "hullmap/sim/ground_truth.hpp"
#include "planning_support.hpp"

namespace hp = hullmap::planning;
using hullmap::sim::TruthShape;

namespace {

TruthShape box(const Eigen::Vector3d& center, const Eigen::Vector3d& size) { return TruthShape::box(center, size); }

hullmap::hulls::Obstacle prismOf(int id, const TruthShape& b) {
  const Eigen::Vector2d c = b.center.head<2>(), h = 0.5 * b.size.head<2>();
  return hullmap::test::prism(id,
                              {c - h, c + Eigen::Vector2d(h.x(), -h.y()), c + h, c + Eigen::Vector2d(-h.x(), h.y())},
                              b.center.z() - 0.5 * b.size.z(), b.center.z() + 0.5 * b.size.z());
}

/// Smallest distance from the path, sampled every `step` metres, to the boxes.
double minDistance(const std::vector<Eigen::Vector3d>& path, const std::vector<TruthShape>& boxes, double step) {
  double best = 1e300;
  for (std::size_t k = 1; k < path.size(); ++k) {
    const int n = std::max(1, static_cast<int>(std::ceil((path[k] - path[k - 1]).norm() / step)));
    for (int s = 0; s <= n; ++s)
      for (const auto& b : boxes)
        best =
            std::min(best, hullmap::test::distanceToSolid(b, path[k - 1] + (path[k] - path[k - 1]) * (double(s) / n)));
  }
  return best;
}

}  // namespace

TEST(PlanningOmpl, PathsRoundAThinWallKeepTheRadiusFromTheTruth) {
  // A 1 cm plate across the way, 4 m wide and 3 m tall, and a post beside it: OMPL's discrete
  // validator steps over the plate; the capsule sweep cannot.
  const std::vector<TruthShape> truth{box({0, 0, 1.5}, {0.01, 4, 3}), box({-1, 2.5, 1}, {0.4, 0.4, 2})};
  const std::vector<hullmap::hulls::Obstacle> obstacles{prismOf(0, truth[0]), prismOf(1, truth[1])};
  hp::PlanRequest request;
  request.start = {-2, 0, 1};
  request.goal = {2, 0, 1};
  request.radius = 0.2;
  hp::OmplParams params;
  params.time_limit = 0.3;
  for (int run = 0; run < 3; ++run) {
    const hp::OmplPlanResult result = hp::planPathOmpl(obstacles, request, params);
    ASSERT_TRUE(result.path) << result.blocked;
    const auto& path = *result.path;
    ASSERT_GE(path.size(), 3u);  // the straight line crosses the plate
    EXPECT_EQ(path.front(), request.start);
    EXPECT_EQ(path.back(), request.goal);
    EXPECT_GE(minDistance(path, truth, 0.002), request.radius - 1e-6);
    for (const auto& p : path) {
      EXPECT_TRUE((p.array() >= result.box.min.array()).all() && (p.array() <= result.box.max.array()).all());
    }
    double length = 0;
    for (std::size_t k = 1; k < path.size(); ++k) length += (path[k] - path[k - 1]).norm();
    EXPECT_NEAR(result.length, length, 1e-9);
    // Round the plate's nearer end (y = 2 + r) or over it (z = 3 + r): at least this long.
    EXPECT_GT(length, 2 * std::hypot(2.0, 2.0) - 1e-6);
    EXPECT_FALSE(result.check.first_colliding_segment);
  }
}

TEST(PlanningOmpl, DefaultBoxHoldsObstaclesStartAndGoal) {
  const TruthShape b = box({3, 4, 1}, {2, 2, 2});
  hp::PlanRequest request;
  request.start = {-1, 0, 0.5};
  request.goal = {1, 1, 1};
  request.radius = 0.5;
  const hp::Box3d bx = hp::omplBoxFor({prismOf(0, b)}, request);
  // margin max(1, 2 * 0.5 + 0.5) = 1.5 in x and y; z from the ground + r (0.5) to the top + margin.
  EXPECT_DOUBLE_EQ(bx.min.x(), -2.5);
  EXPECT_DOUBLE_EQ(bx.min.y(), -1.5);
  EXPECT_DOUBLE_EQ(bx.max.x(), 5.5);
  EXPECT_DOUBLE_EQ(bx.max.y(), 6.5);
  EXPECT_DOUBLE_EQ(bx.min.z(), 0.5);
  EXPECT_DOUBLE_EQ(bx.max.z(), 3.5);
}

TEST(PlanningOmpl, BlockedEndsAndBadParametersAreSaid) {
  const std::vector<hullmap::hulls::Obstacle> obstacles{prismOf(0, box({0, 0, 1}, {1, 1, 2}))};
  hp::PlanRequest request;
  request.start = {0.1, 0, 1};
  request.goal = {3, 0, 1};
  request.radius = 0.1;
  hp::OmplParams params;
  params.time_limit = 0.05;
  const auto inside = hp::planPathOmpl(obstacles, request, params);
  EXPECT_FALSE(inside.path);
  EXPECT_NE(inside.blocked.find("start (0.1, 0, 1) is inside obstacle 0"), std::string::npos) << inside.blocked;
  request.start = {-3, 0, 1};
  params.box = hp::Box3d{{-2, -2, 0}, {4, 2, 3}};
  const auto outside = hp::planPathOmpl(obstacles, request, params);
  EXPECT_FALSE(outside.path);
  EXPECT_NE(outside.blocked.find("outside the planning box"), std::string::npos) << outside.blocked;
  for (const double bad : {0.0, -1.0, std::nan("")}) {
    params.time_limit = bad;
    EXPECT_EQ(hullmap::test::refusedParameter([&] { hp::planPathOmpl(obstacles, request, params); }), "time_limit");
  }
  params.time_limit = 0.05;
  params.clearance_scale = 0;
  EXPECT_EQ(hullmap::test::refusedParameter([&] { hp::planPathOmpl(obstacles, request, params); }), "clearance_scale");
  params.clearance_scale = 0.5;
  request.goal.x() = std::nan("");
  EXPECT_EQ(hullmap::test::refusedParameter([&] { hp::planPathOmpl(obstacles, request, params); }), "start/goal");
}
