#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/planning/fleet.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "planning_support.hpp"

namespace hullmap {
namespace {

using Eigen::Vector3d;
using planning::TimedPath;

/// Dense-sampling oracle: the smallest pairwise distance at instants 1 ms apart.
double sampledSeparation(const std::vector<TimedPath>& paths) {
  double end = 0;
  for (const auto& p : paths) end = std::max(end, p.back().t);
  double best = 1e300;
  for (double t = 0; t <= end + 1e-3; t += 1e-3)
    for (std::size_t i = 0; i < paths.size(); ++i)
      for (std::size_t j = i + 1; j < paths.size(); ++j)
        best = std::min(best, (planning::positionAt(paths[i], t) - planning::positionAt(paths[j], t)).norm());
  return best;
}

void expectSafeFleet(const sim::Scene& scene, const std::vector<planning::FleetTask>& tasks,
                     const planning::FleetResult& result, const planning::FleetParams& params) {
  const std::vector<sim::TruthShape> truth = scene.truth.primitives();
  std::vector<TimedPath> routed;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    if (!result.paths[i]) continue;
    const TimedPath& path = *result.paths[i];
    EXPECT_TRUE(path.front().position.isApprox(tasks[i].start));
    EXPECT_TRUE(path.back().position.isApprox(tasks[i].goal));
    EXPECT_EQ(path.front().t, 0.0);
    for (std::size_t k = 1; k < path.size(); ++k) {
      const double dt = path[k].t - path[k - 1].t;
      ASSERT_GT(dt, 0);
      EXPECT_LE((path[k].position - path[k - 1].position).norm() / dt, params.speed * (1 + 1e-9)) << "drone " << i;
      const int steps =
          std::max(1, static_cast<int>(std::ceil((path[k].position - path[k - 1].position).norm() / 0.01)));
      for (int s = 0; s <= steps; ++s) {
        const Vector3d p = path[k - 1].position + (path[k].position - path[k - 1].position) * (double(s) / steps);
        for (const auto& o : truth)
          ASSERT_GE(test::distanceToSolid(o, p), params.radius - 1e-9) << "drone " << i << " at " << p.transpose();
      }
    }
    routed.push_back(path);
  }
  const double sampled = sampledSeparation(routed);
  EXPECT_GE(sampled, 2 * params.radius - 1e-9);
  EXPECT_LE(result.min_separation, sampled + 1e-9);  // the exact minimum is no larger than any sample
  EXPECT_GE(result.min_separation, 2 * params.radius);
}

TEST(Fleet, RoutesDronesInTheSampleSceneApartAndClearOfTheTruth) {
  sim::SceneParams sp;
  sp.obstacles = 10;
  sp.points = 100;
  const sim::Scene scene = sim::generateScene(sp);
  const auto obstacles = test::truthObstacles(scene);
  planning::FleetParams params;
  params.radius = 0.2;
  params.speed = 1.0;
  planning::RoadmapParams rp;
  rp.z0 = 1.0 - params.radius;
  rp.z1 = 1.0 + params.radius;
  rp.bounds = planning::Bounds2d{-5, -5, 5, 5};
  const planning::PathPlanner planner(obstacles, planning::buildRoadmap(obstacles, rp));

  // Ten drones on a circle, each flying to the opposite side: every path crosses the middle.
  std::vector<planning::FleetTask> tasks;
  for (int i = 0; i < 10; ++i) {
    const double a = 2 * M_PI * i / 10;
    tasks.push_back(
        {Vector3d(4.4 * std::cos(a), 4.4 * std::sin(a), 1.0), Vector3d(-4.4 * std::cos(a), -4.4 * std::sin(a), 1.0)});
  }
  const auto result = planning::planFleet(planner, tasks, params);
  ASSERT_EQ(result.paths.size(), tasks.size());
  std::size_t routed = 0;
  for (const auto& p : result.paths) routed += p.has_value();
  EXPECT_GE(routed, 8u) << (result.reasons.empty() ? "" : result.reasons.front());
  expectSafeFleet(scene, tasks, result, params);
  std::cout << routed << "/10 routed, min separation " << result.min_separation << " m\n";
}

TEST(Fleet, HeadOnSwapInACorridorWaitsOrDetoursAndNamesTheUnroutable) {
  // Two drones swap ends of a 1 m wide corridor with a wide hall at each end.
  sim::Scene scene;
  scene.truth.add(sim::TruthShape::box(Vector3d(0, 1.5, 1.5), Vector3d(4, 2, 3)));
  scene.truth.add(sim::TruthShape::box(Vector3d(0, -1.5, 1.5), Vector3d(4, 2, 3)));
  const auto obstacles = test::truthObstacles(scene);
  planning::FleetParams params;
  params.radius = 0.2;
  params.speed = 2.0;
  planning::RoadmapParams rp;
  rp.bounds = planning::Bounds2d{-5, -2.5, 5, 2.5};
  const planning::PathPlanner planner(obstacles, planning::buildRoadmap(obstacles, rp));
  std::vector<planning::FleetTask> tasks{{Vector3d(-4, 0, 1), Vector3d(4, 0, 1)},
                                         {Vector3d(4, 0, 1), Vector3d(-4, 0, 1)}};
  const auto result = planning::planFleet(planner, tasks, params);
  ASSERT_TRUE(result.paths[0] && result.paths[1]) << (result.reasons.empty() ? "" : result.reasons.front());
  expectSafeFleet(scene, tasks, result, params);

  // A third drone whose start is within 2R of the first's: it cannot be routed, and is named.
  tasks.push_back({Vector3d(-4, 0.3, 1), Vector3d(4, 1, 1)});
  const auto crowded = planning::planFleet(planner, tasks, params);
  ASSERT_EQ(crowded.unrouted, std::vector<std::size_t>{2});
  EXPECT_NE(crowded.reasons[0].find("drone 2"), std::string::npos);
  expectSafeFleet(scene, tasks, crowded, params);

  // The floor is an obstacle: a drone that starts under it is named with the floor, as plan names it.
  const std::vector<collision::Surface> floor{collision::Surface::plane("floor", Vector3d::UnitZ(), 0.0)};
  const planning::PathPlanner on_floor(obstacles, planning::buildRoadmap(obstacles, rp, floor), floor);
  const auto under = planning::planFleet(on_floor, {{Vector3d(-4, 0, -1), Vector3d(4, 0, 1)}}, params);
  ASSERT_EQ(under.unrouted, std::vector<std::size_t>{0});
  EXPECT_NE(under.reasons[0].find("start (-4, 0, -1) is inside the floor or within the radius of it"),
            std::string::npos)
      << under.reasons[0];

  params.speed = 0;
  EXPECT_EQ(test::refusedParameter([&] { planning::planFleet(planner, tasks, params); }), "speed");
  EXPECT_EQ(test::refusedParameter([] { planning::positionAt({}, 0.0); }), "path");
}

}  // namespace
}  // namespace hullmap
