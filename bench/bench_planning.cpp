// Planning benchmarks for docs/BENCHMARKS.md (bench/section_planning.sh formats them). One JSON
// object a line on stdout:
//   {"kind":"roadmap", obstacles, median_ms, edges}
//   {"kind":"plan", queries, connected, found, plan_ms_median, planner_ms_median, ratio_median, ratio_max}
//   {"kind":"ompl", scene, motion_check, queries, found, clear, collided, length_mean, ...}
//   {"kind":"fleet", drones, routed, ms, min_separation, radius}
//
// usage: hullmap_bench_planning ROOM_OBSTACLES_JSON [--ompl-time S] [--ompl-queries N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <iostream>
#include <queue>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/planning/fleet.hpp"
#include "hullmap/planning/ompl_planner.hpp"
#include "hullmap/planning/path_planner.hpp"
#include "hullmap/planning/roadmap.hpp"

namespace hp = hullmap::planning;
using hullmap::hulls::Obstacle;

namespace {

double seconds(std::chrono::steady_clock::time_point a) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// A prism over [z0, z1] on the counter-clockwise polygon.
Obstacle prism(int id, const std::vector<Eigen::Vector2d>& polygon, double z0, double z1) {
  Obstacle o;
  o.id = id;
  const int n = static_cast<int>(polygon.size());
  for (const auto& p : polygon) o.hull.vertices.emplace_back(p.x(), p.y(), z0);
  for (const auto& p : polygon) o.hull.vertices.emplace_back(p.x(), p.y(), z1);
  for (int i = 1; i + 1 < n; ++i) {
    o.hull.triangles.push_back({0, i + 1, i});
    o.hull.triangles.push_back({n, n + i, n + i + 1});
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    o.hull.triangles.push_back({i, j, n + j});
    o.hull.triangles.push_back({i, n + j, n + i});
  }
  o.footprint.polygon = polygon;
  o.footprint.z_min = z0;
  o.footprint.z_max = z1;
  o.aabb_min = Eigen::Vector3d(1e300, 1e300, z0);
  o.aabb_max = Eigen::Vector3d(-1e300, -1e300, z1);
  for (const auto& p : polygon) {
    o.aabb_min.head<2>() = o.aabb_min.head<2>().cwiseMin(p);
    o.aabb_max.head<2>() = o.aabb_max.head<2>().cwiseMax(p);
  }
  o.centroid = 0.5 * (o.aabb_min + o.aabb_max);
  return o;
}

/// `n` rotated boxes (0.3-1.2 m sides, 0-3 m tall) in a square of side 3 sqrt(n) m, at least 0.3 m
/// apart (by their circumscribed circles); `thin` of them are 2 cm plates 2 m long.
std::vector<Obstacle> randomScene(int n, int thin, unsigned seed, double& side) {
  side = 3.0 * std::sqrt(static_cast<double>(n));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Obstacle> out;
  std::vector<std::pair<Eigen::Vector2d, double>> placed;
  for (int tries = 0; static_cast<int>(out.size()) < n && tries < 100000; ++tries) {
    const bool plate = static_cast<int>(out.size()) < thin;
    const double a = plate ? 0.02 : 0.3 + 0.9 * u(rng), b = plate ? 2.0 : 0.3 + 0.9 * u(rng);
    const Eigen::Vector2d c(side * u(rng), side * u(rng));
    const double reach = 0.5 * std::hypot(a, b);
    bool ok = true;
    for (const auto& [q, rq] : placed) ok = ok && (q - c).norm() > reach + rq + 0.3;
    if (!ok) continue;
    placed.emplace_back(c, reach);
    const double t = M_PI * u(rng);
    const Eigen::Vector2d ex(std::cos(t), std::sin(t)), ey(-std::sin(t), std::cos(t));
    out.push_back(prism(static_cast<int>(out.size()),
                        {c - 0.5 * a * ex - 0.5 * b * ey, c + 0.5 * a * ex - 0.5 * b * ey,
                         c + 0.5 * a * ex + 0.5 * b * ey, c - 0.5 * a * ex + 0.5 * b * ey},
                        0.0, 3.0));
  }
  return out;
}

double segmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * d)).norm();
}

/// Distance from p to the footprint (0 inside).
double footprintDistance(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  bool inside = true;
  double best = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& a = poly[i];
    const auto& b = poly[(i + 1) % poly.size()];
    const Eigen::Vector2d e = b - a, w = p - a;
    inside = inside && e.x() * w.y() - e.y() * w.x() >= 0;
    best = std::min(best, segmentDistance(p, a, b));
  }
  return inside ? 0.0 : best;
}

/// Shortest path on a 16-connected grid of cells whose centres keep `clearance` from every
/// footprint (the oracle of the tests, finer). Its length is within 2.7% above the true shortest
/// path through the free cells.
struct Grid {
  double cell;
  int n;
  std::vector<char> free;
  Grid(const std::vector<Obstacle>& obstacles, double side, double cell_size, double clearance)
      : cell(cell_size), n(static_cast<int>(std::ceil(side / cell_size))), free(static_cast<std::size_t>(n) * n, 1) {
    for (const auto& o : obstacles) {
      const int i0 = std::max(0, static_cast<int>((o.aabb_min.x() - clearance) / cell) - 1);
      const int i1 = std::min(n - 1, static_cast<int>((o.aabb_max.x() + clearance) / cell) + 1);
      const int j0 = std::max(0, static_cast<int>((o.aabb_min.y() - clearance) / cell) - 1);
      const int j1 = std::min(n - 1, static_cast<int>((o.aabb_max.y() + clearance) / cell) + 1);
      for (int i = i0; i <= i1; ++i)
        for (int j = j0; j <= j1; ++j)
          if (footprintDistance(o.footprint.polygon, centre(i, j)) < clearance) free[index(i, j)] = 0;
    }
  }
  Eigen::Vector2d centre(int i, int j) const { return {(i + 0.5) * cell, (j + 0.5) * cell}; }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(i) * n + j; }
  bool isFree(const Eigen::Vector2d& p) const {
    const int i = static_cast<int>(p.x() / cell), j = static_cast<int>(p.y() / cell);
    return i >= 0 && j >= 0 && i < n && j < n && free[index(i, j)];
  }
  /// Length from the cell of a to the cell of b, plus the two end offsets; < 0 when not connected.
  double shortest(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
    static const int moves[16][2] = {{1, 0}, {-1, 0}, {0, 1},  {0, -1},  {1, 1}, {1, -1}, {-1, 1}, {-1, -1},
                                     {2, 1}, {2, -1}, {-2, 1}, {-2, -1}, {1, 2}, {1, -2}, {-1, 2}, {-1, -2}};
    const int ai = static_cast<int>(a.x() / cell), aj = static_cast<int>(a.y() / cell);
    const int bi = static_cast<int>(b.x() / cell), bj = static_cast<int>(b.y() / cell);
    std::vector<double> dist(free.size(), 1e300);
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    dist[index(ai, aj)] = 0;
    open.emplace(0.0, index(ai, aj));
    const std::size_t target = index(bi, bj);
    while (!open.empty()) {
      const auto [d, v] = open.top();
      open.pop();
      if (d > dist[v]) continue;
      if (v == target) break;
      const int i = static_cast<int>(v / n), j = static_cast<int>(v % n);
      for (const auto& m : moves) {
        const int x = i + m[0], y = j + m[1];
        if (x < 0 || y < 0 || x >= n || y >= n || !free[index(x, y)]) continue;
        // knight moves pass between two cells: both must be free
        if (std::abs(m[0]) + std::abs(m[1]) == 3 &&
            (!free[index(i + m[0] / 2 * (std::abs(m[0]) == 2), j + m[1] / 2 * (std::abs(m[1]) == 2))] ||
             !free[index(i + (m[0] > 0) - (m[0] < 0), j + (m[1] > 0) - (m[1] < 0))]))
          continue;
        // diagonal moves too: the two cells beside the diagonal must be free
        if (std::abs(m[0]) + std::abs(m[1]) == 2 && (!free[index(i + m[0], j)] || !free[index(i, j + m[1])])) continue;
        const double nd = d + cell * std::hypot(m[0], m[1]);
        if (nd < dist[index(x, y)]) {
          dist[index(x, y)] = nd;
          open.emplace(nd, index(x, y));
        }
      }
    }
    if (dist[target] >= 1e300) return -1;
    return dist[target] + (a - centre(ai, aj)).norm() + (b - centre(bi, bj)).norm();
  }
};

void roadmapRows() {
  for (const int n : {10, 100, 1000}) {
    double side = 0;
    const auto obstacles = randomScene(n, 0, 11, side);
    hp::RoadmapParams params;
    params.z0 = 0.5;
    params.z1 = 1.5;
    std::vector<double> ms, cpu_ms;
    std::size_t edges = 0;
    for (int run = 0; run < (n >= 1000 ? 3 : 7); ++run) {
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      const hp::Roadmap map = hp::buildRoadmap(obstacles, params);
      cpu_ms.push_back(1e3 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
      ms.push_back(1e3 * seconds(t0));
      edges = map.edges.size();
    }
    std::cout << nlohmann::json{{"kind", "roadmap"},
                                {"obstacles", obstacles.size()},
                                {"median_ms", median(ms)},
                                {"cpu_ms", median(cpu_ms)},
                                {"edges", edges}}
                     .dump()
              << std::endl;
  }
}

struct Query {
  Eigen::Vector3d start, goal;
};

std::vector<Query> freeQueries(const Grid& grid, double side, int count, unsigned seed, bool connected_only,
                               std::vector<double>* grid_lengths) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.05 * side, 0.95 * side);
  std::vector<Query> out;
  while (static_cast<int>(out.size()) < count) {
    const Eigen::Vector2d a(u(rng), u(rng)), b(u(rng), u(rng));
    if (!grid.isFree(a) || !grid.isFree(b) || (a - b).norm() < 0.5 * side) continue;
    double len = 0;
    if (connected_only && (len = grid.shortest(a, b)) < 0) continue;
    if (grid_lengths) grid_lengths->push_back(len);
    out.push_back({{a.x(), a.y(), 1.0}, {b.x(), b.y(), 1.0}});
  }
  return out;
}

void planRows() {
  const double radius = 0.2;
  double side = 0;
  const auto obstacles = randomScene(25, 0, 5, side);
  const Grid grid(obstacles, side, 0.02, radius);
  std::vector<double> grid_lengths;
  const auto queries = freeQueries(grid, side, 20, 3, true, &grid_lengths);
  std::vector<double> total_ms, planner_ms, ratios;
  int found = 0;
  for (std::size_t q = 0; q < queries.size(); ++q) {
    hp::PlanRequest request;
    request.start = queries[q].start;
    request.goal = queries[q].goal;
    request.radius = radius;
    const auto t0 = std::chrono::steady_clock::now();
    const auto params = hp::roadmapParamsFor(obstacles, {request.start, request.goal}, radius);
    const hp::PathPlanner planner(obstacles, hp::buildRoadmap(obstacles, params));
    const auto t1 = std::chrono::steady_clock::now();
    const hp::PlanResult result = planner.plan(request);
    planner_ms.push_back(1e3 * seconds(t1));
    total_ms.push_back(1e3 * seconds(t0));
    if (!result.path) continue;
    ++found;
    ratios.push_back(result.length / grid_lengths[q]);
  }
  std::cout << nlohmann::json{{"kind", "plan"},
                              {"obstacles", obstacles.size()},
                              {"side", side},
                              {"radius", radius},
                              {"queries", queries.size()},
                              {"found", found},
                              {"total_ms_median", median(total_ms)},
                              {"plan_ms_median", median(planner_ms)},
                              {"ratio_median", median(ratios)},
                              {"ratio_max", ratios.empty() ? 0.0 : *std::max_element(ratios.begin(), ratios.end())}}
                   .dump()
            << std::endl;
}

void omplRows(double time_limit, int count) {
  const double radius = 0.05;
  for (const int thin : {0, 6}) {
    double side = 0;
    const auto obstacles = randomScene(16, thin, 9, side);
    const Grid grid(obstacles, side, 0.05, radius);
    const auto queries = freeQueries(grid, side, count, 4, false, nullptr);
    const hullmap::collision::HullChecker checker(obstacles);
    for (const auto check : {hp::OmplMotionCheck::kExact, hp::OmplMotionCheck::kDiscrete}) {
      int found = 0, clear = 0, collided = 0;
      double length = 0, worst_depth = 0;
      for (const auto& q : queries) {
        hp::PlanRequest request;
        request.start = q.start;
        request.goal = q.goal;
        request.radius = radius;
        hp::OmplParams params;
        params.time_limit = time_limit;
        params.motion_check = check;
        const auto result = hp::planPathOmpl(obstacles, request, params);
        if (result.planner_path.empty()) continue;
        ++found;
        double len = 0;
        for (std::size_t k = 1; k < result.planner_path.size(); ++k)
          len += (result.planner_path[k] - result.planner_path[k - 1]).norm();
        length += len;
        if (result.path) {
          ++clear;
          continue;
        }
        ++collided;
        // How deep: the smallest clearance of the sphere centre along the path, densely sampled.
        for (std::size_t k = 1; k < result.planner_path.size(); ++k)
          for (int s = 0; s <= 200; ++s) {
            const Eigen::Vector3d p =
                result.planner_path[k - 1] + (result.planner_path[k] - result.planner_path[k - 1]) * (s / 200.0);
            const auto c = checker.check({p, p}, 0.0);
            worst_depth = std::max(worst_depth, radius - (c.collides ? 0.0 : c.clearance));
          }
      }
      std::cout << nlohmann::json{{"kind", "ompl"},
                                  {"thin", thin},
                                  {"obstacles", obstacles.size()},
                                  {"side", side},
                                  {"radius", radius},
                                  {"time_limit", time_limit},
                                  {"motion_check", check == hp::OmplMotionCheck::kExact ? "exact" : "discrete"},
                                  {"queries", queries.size()},
                                  {"found", found},
                                  {"clear", clear},
                                  {"collided", collided},
                                  {"length_mean", found ? length / found : 0.0},
                                  {"worst_depth", worst_depth}}
                       .dump()
                << std::endl;
    }
  }
}

void fleetRow(const std::string& room_obstacles) {
  const auto obstacles = hullmap::pipeline::readObstacles(room_obstacles);
  const double radius = 0.2;
  std::vector<hp::FleetTask> tasks;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 10; ++i) {
    const double y = -4.0 + 8.0 * i / 9.0;
    tasks.push_back({{-4.5, y, 1.0}, {4.5, -y, 1.0}});
    points.push_back(tasks.back().start);
    points.push_back(tasks.back().goal);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const hp::PathPlanner planner(obstacles,
                                hp::buildRoadmap(obstacles, hp::roadmapParamsFor(obstacles, points, radius)));
  hp::FleetParams params;
  params.radius = radius;
  params.speed = 1.0;
  const hp::FleetResult result = hp::planFleet(planner, tasks, params);
  const double ms = 1e3 * seconds(t0);
  std::cout << nlohmann::json{{"kind", "fleet"},
                              {"drones", tasks.size()},
                              {"routed", tasks.size() - result.unrouted.size()},
                              {"ms", ms},
                              {"min_separation", result.min_separation},
                              {"radius", radius},
                              {"obstacles", obstacles.size()}}
                   .dump()
            << std::endl;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: " << argv[0] << " ROOM_OBSTACLES_JSON [--ompl-time S] [--ompl-queries N]\n";
    return 2;
  }
  double ompl_time = 1.0;
  int ompl_queries = 8;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--ompl-time")
      ompl_time = std::atof(argv[i + 1]);
    else if (flag == "--ompl-queries")
      ompl_queries = std::atoi(argv[i + 1]);
  }
  roadmapRows();
  planRows();
  fleetRow(argv[1]);
  omplRows(ompl_time, ompl_queries);
  return 0;
}
