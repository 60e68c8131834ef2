#include <cmath>
#include <iostream>
#include <queue>
#include <random>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "hullmap/core/error.hpp"
#include "hullmap/planning/path_planner.hpp"
#include "hullmap/sim/sample_scene.hpp"
#include "planning_support.hpp"

namespace hullmap {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

/// The oracle: a 2D grid over the room at height z whose cells are free when their centre keeps
/// `clearance` from every true solid (exact distance); Dijkstra over 8-neighbours between free cells.
struct GridOracle {
  double cell, x0, y0;
  int n;
  std::vector<char> free;
  GridOracle(const sim::Scene& scene, double room, double z, double clearance, double cell_size)
      : cell(cell_size), x0(-room / 2), y0(-room / 2), n(static_cast<int>(std::ceil(room / cell_size))) {
    free.assign(static_cast<std::size_t>(n) * n, 1);
    const std::vector<sim::TruthShape> truth = scene.truth.primitives();
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (const auto& o : truth)
          if (test::distanceToSolid(o, center(i, j, z)) < clearance) free[index(i, j)] = 0;
  }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(i) * n + j; }
  Vector3d center(int i, int j, double z) const { return {x0 + (i + 0.5) * cell, y0 + (j + 0.5) * cell, z}; }
  std::pair<int, int> cellOf(const Vector3d& p) const {
    return {static_cast<int>((p.x() - x0) / cell), static_cast<int>((p.y() - y0) / cell)};
  }
  bool isFree(const Vector3d& p) const {
    const auto [i, j] = cellOf(p);
    return i >= 0 && j >= 0 && i < n && j < n && free[index(i, j)];
  }
  /// Shortest 8-connected path length between the cells of a and b (+inf when not connected).
  double shortest(const Vector3d& a, const Vector3d& b) const {
    const auto [ai, aj] = cellOf(a);
    const auto [bi, bj] = cellOf(b);
    std::vector<double> dist(free.size(), 1e300);
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    dist[index(ai, aj)] = 0;
    open.emplace(0.0, index(ai, aj));
    while (!open.empty()) {
      const auto [d, v] = open.top();
      open.pop();
      if (d > dist[v]) continue;
      const int i = static_cast<int>(v / n), j = static_cast<int>(v % n);
      if (i == bi && j == bj) return d;
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj) {
          const int u = i + di, w = j + dj;
          if ((di == 0 && dj == 0) || u < 0 || w < 0 || u >= n || w >= n || !free[index(u, w)]) continue;
          const double c = d + cell * std::hypot(di, dj);
          if (c < dist[index(u, w)]) {
            dist[index(u, w)] = c;
            open.emplace(c, index(u, w));
          }
        }
    }
    return 1e300;
  }
};

/// Smallest distance from the densely sampled path (1 cm) to the true solids.
double pathClearance(const sim::Scene& scene, const std::vector<Vector3d>& path) {
  const std::vector<sim::TruthShape> truth = scene.truth.primitives();
  double best = 1e300;
  for (std::size_t k = 1; k < path.size(); ++k) {
    const int steps = std::max(1, static_cast<int>(std::ceil((path[k] - path[k - 1]).norm() / 0.01)));
    for (int s = 0; s <= steps; ++s) {
      const Vector3d p = path[k - 1] + (path[k] - path[k - 1]) * (static_cast<double>(s) / steps);
      for (const auto& o : truth) best = std::min(best, test::distanceToSolid(o, p));
    }
  }
  return best;
}

TEST(PathPlanner, FindsWhatTheGridOracleConnectsAndKeepsTheRadiusFromTheTruth) {
  const double z = 1.0;
  int connected = 0, found = 0, spurious = 0;
  double ratio_sum = 0, ratio_max = 0;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    sim::SceneParams params;
    params.seed = seed;
    params.obstacles = 14;
    params.points = 100;
    const sim::Scene scene = sim::generateScene(params);
    const auto obstacles = test::truthObstacles(scene);
    for (const double radius : {0.2, 0.4}) {
      planning::RoadmapParams rp;
      rp.z0 = z - radius;
      rp.z1 = z + radius;
      rp.bounds =
          planning::Bounds2d{-params.room_size / 2, -params.room_size / 2, params.room_size / 2, params.room_size / 2};
      const planning::PathPlanner planner(obstacles, planning::buildRoadmap(obstacles, rp));
      const GridOracle oracle(scene, params.room_size, z, radius + 0.1, 0.05);
      std::mt19937 rng(static_cast<unsigned>(seed * 10 + radius * 10));
      std::uniform_real_distribution<double> u(-params.room_size / 2 + radius + 0.1,
                                               params.room_size / 2 - radius - 0.1);
      for (int trial = 0; trial < 40; ++trial) {
        const Vector3d start(u(rng), u(rng), z), goal(u(rng), u(rng), z);
        if (!oracle.isFree(start) || !oracle.isFree(goal)) continue;
        const double grid = oracle.shortest(start, goal);
        const planning::PlanResult result = planner.plan({start, goal, radius, std::nullopt});
        if (result.path) {
          EXPECT_GE(pathClearance(scene, *result.path), radius - 1e-9)
              << "seed " << seed << " radius " << radius << " from " << start.transpose() << " to " << goal.transpose();
          EXPECT_FALSE(planner.checker().checkPath(*result.path, radius).first_colliding_segment);
          EXPECT_TRUE(result.path->front().isApprox(start) && result.path->back().isApprox(goal));
        } else {
          EXPECT_FALSE(result.blocked.empty());
        }
        if (grid >= 1e300) {
          spurious += result.path.has_value();  // allowed: the oracle demands 0.1 m more clearance
          continue;
        }
        ++connected;
        if (!result.path) {
          ADD_FAILURE() << "seed " << seed << " radius " << radius << ": grid connects " << start.transpose() << " to "
                        << goal.transpose() << " but plan says: " << result.blocked;
          continue;
        }
        ++found;
        const double ratio = result.length / std::max(grid, 1e-9);
        ratio_sum += ratio;
        ratio_max = std::max(ratio_max, ratio);
      }
    }
  }
  ASSERT_GT(connected, 100);
  EXPECT_GE(found, 0.99 * connected) << found << " of " << connected;
  std::ostringstream summary;
  summary << found << "/" << connected << " found; length / grid shortest: mean " << ratio_sum / found << ", max "
          << ratio_max << "; " << spurious << " found where the grid at R + 0.1 is disconnected";
  RecordProperty("summary", summary.str());
  std::cout << summary.str() << "\n";
  // The grid path is 8-connected at R + 0.1 (longer than the true shortest at R); ours must not be
  // much longer than it.
  EXPECT_LE(ratio_sum / found, 1.05);
}

TEST(PathPlanner, SaysWhereItIsBlocked) {
  // A wall of two boxes with a 0.5 m gap: radius 0.2 passes, radius 0.3 is blocked at the gap, and
  // the bounds hug the wall so there is no way round.
  const auto left = test::prism(1, {{-5, -0.5}, {-0.25, -0.5}, {-0.25, 0.5}, {-5, 0.5}}, 0, 3);
  const auto right = test::prism(2, {{0.25, -0.5}, {5, -0.5}, {5, 0.5}, {0.25, 0.5}}, 0, 3);
  planning::RoadmapParams rp;
  rp.bounds = planning::Bounds2d{-5, -4, 5, 4};
  const planning::PathPlanner planner({left, right}, planning::buildRoadmap({left, right}, rp));
  const Vector3d start(-2, -3, 1), goal(2, 3, 1);
  const auto ok = planner.plan({start, goal, 0.2, std::nullopt});
  ASSERT_TRUE(ok.path) << ok.blocked;
  EXPECT_FALSE(planner.checker().checkPath(*ok.path, 0.2).first_colliding_segment);
  const auto blocked = planner.plan({start, goal, 0.3, std::nullopt});
  EXPECT_FALSE(blocked.path);
  EXPECT_NE(blocked.blocked.find("narrows to clearance 0.25"), std::string::npos) << blocked.blocked;
  const auto inside = planner.plan({Vector3d(-3, 0, 1), goal, 0.2, std::nullopt});
  EXPECT_FALSE(inside.path);
  EXPECT_NE(inside.blocked.find("start (-3, 0, 1) is inside obstacle 1"), std::string::npos) << inside.blocked;
  EXPECT_EQ(test::refusedParameter([&] { planner.plan({start, goal, -1, std::nullopt}); }), "radius");
  EXPECT_EQ(test::refusedParameter([&] { planner.plan({start, goal, 0.2, std::nan("")}); }), "flight_z");
}

}  // namespace
}  // namespace hullmap
