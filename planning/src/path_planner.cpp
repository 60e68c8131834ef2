#include "hullmap/planning/path_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <sstream>
#include <utility>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/error.hpp"
#include "point_text.hpp"

namespace hullmap::planning {
namespace {

/// Roadmap points tried, nearest first, when connecting an end; connections kept per end.
constexpr std::size_t kConnectTries = 400;
constexpr std::size_t kConnections = 6;
/// Alternative routes: after the shortest one, up to kRoutes - 1 more with the links into vertices
/// of the earlier routes this many times longer; the shortest after shortening wins.
constexpr int kRoutes = 3;
constexpr double kDetourPenalty = 3.0;

Eigen::Vector3d lift(const Eigen::Vector2d& p, double z) { return {p.x(), p.y(), z}; }

}  // namespace

struct PathPlanner::Impl {
  Roadmap roadmap;
  collision::HullChecker checker;
  Graph graph;

  Impl(const std::vector<hulls::Obstacle>& obstacles, Roadmap map, std::vector<collision::Surface> surfaces)
      : roadmap(std::move(map)), checker(obstacles, std::move(surfaces)) {
    for (const auto& n : roadmap.nodes) graph.position.push_back(n.position);
    graph.links.resize(graph.position.size());
    for (const auto& e : roadmap.edges) {
      int previous = e.from;
      for (std::size_t k = 1; k < e.polyline.size(); ++k) {
        int current = e.to;
        if (k + 1 < e.polyline.size()) {
          current = static_cast<int>(graph.position.size());
          graph.position.push_back(e.polyline[k]);
          graph.links.emplace_back();
        }
        const double length = (e.polyline[k] - e.polyline[k - 1]).norm();
        graph.links[previous].push_back({current, length, e.clearance});
        graph.links[current].push_back({previous, length, e.clearance});
        previous = current;
      }
    }
  }

  bool clear(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius) const {
    return !checker.check({a, b}, radius).collides;
  }

  /// Roadmap vertices (with a usable link) that `end` sees with clearance, with the segment length.
  std::vector<std::pair<int, double>> connect(const Eigen::Vector3d& end, double z, double radius, double floor) const {
    std::vector<std::pair<double, int>> order;
    for (std::size_t v = 0; v < graph.position.size(); ++v) {
      bool usable = false;
      for (const auto& l : graph.links[v]) usable = usable || l.clearance >= floor;
      if (usable) order.emplace_back((graph.position[v] - end.head<2>()).squaredNorm(), static_cast<int>(v));
    }
    const std::size_t tries = std::min(order.size(), kConnectTries);
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(tries), order.end());
    std::vector<std::pair<int, double>> out;
    for (std::size_t k = 0; k < tries && out.size() < kConnections; ++k) {
      const Eigen::Vector3d p = lift(graph.position[order[k].second], z);
      if (clear(end, p, radius)) out.emplace_back(order[k].second, (p - end).norm());
    }
    return out;
  }

  /// A* from the start connections to the goal connections over links with clearance >= floor.
  std::optional<std::vector<int>> search(const std::vector<std::pair<int, double>>& from,
                                         const std::vector<std::pair<int, double>>& to, const Eigen::Vector2d& goal,
                                         double floor, const std::vector<char>& penalized = {}) const {
    const std::size_t n = graph.position.size();
    const int target = static_cast<int>(n);  // the goal itself
    std::vector<double> exit(n, kInf);
    for (const auto& [v, len] : to) exit[v] = std::min(exit[v], len);
    std::vector<double> cost(n + 1, kInf);
    std::vector<int> parent(n + 1, -1);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    auto h = [&](int v) { return v == target ? 0.0 : (graph.position[v] - goal).norm(); };
    for (const auto& [v, len] : from)
      if (len < cost[v]) {
        cost[v] = len;
        open.emplace(len + h(v), v);
      }
    while (!open.empty()) {
      // Named copies rather than a structured binding: C++17 lambdas (relax, below) cannot capture one.
      const double f = open.top().first;
      const int v = open.top().second;
      open.pop();
      if (f > cost[v] + h(v) + 1e-12) continue;
      if (v == target) break;
      auto relax = [&](int w, double c) {
        if (c < cost[w]) {
          cost[w] = c;
          parent[w] = v;
          open.emplace(c + h(w), w);
        }
      };
      if (exit[v] < kInf) relax(target, cost[v] + exit[v]);
      for (const auto& l : graph.links[v])
        if (l.clearance >= floor)
          relax(l.to, cost[v] + l.length * (!penalized.empty() && penalized[l.to] ? kDetourPenalty : 1.0));
    }
    if (cost[target] == kInf) return std::nullopt;
    std::vector<int> chain;
    for (int v = parent[target]; v >= 0; v = parent[v]) chain.push_back(v);
    std::reverse(chain.begin(), chain.end());
    return chain;
  }

  /// Where the widest roadmap way between the two connection sets is narrowest (bottleneck
  /// Dijkstra over all links), or "" when the roadmap does not join them at all.
  std::string narrowest(const std::vector<std::pair<int, double>>& from,
                        const std::vector<std::pair<int, double>>& to) const {
    const std::size_t n = graph.position.size();
    std::vector<double> width(n, -kInf);
    std::vector<int> parent(n, -1);
    std::priority_queue<std::pair<double, int>> open;
    for (const auto& [v, len] : from) {
      width[v] = kInf;
      open.emplace(kInf, v);
    }
    std::vector<char> is_goal(n, 0);
    for (const auto& [v, len] : to) is_goal[v] = 1;
    int reached = -1;
    while (!open.empty()) {
      const auto [w, v] = open.top();
      open.pop();
      if (w < width[v]) continue;
      if (is_goal[v]) {
        reached = v;
        break;
      }
      for (const auto& l : graph.links[v]) {
        const double c = std::min(w, l.clearance);
        if (c > width[l.to]) {
          width[l.to] = c;
          parent[l.to] = v;
          open.emplace(c, l.to);
        }
      }
    }
    if (reached < 0) return "";
    double best = kInf;
    Eigen::Vector2d where = graph.position[reached];
    for (int v = reached; parent[v] >= 0; v = parent[v])
      for (const auto& l : graph.links[v])
        if (l.to == parent[v] && l.clearance < best) {
          best = l.clearance;
          where = 0.5 * (graph.position[v] + graph.position[l.to]);
        }
    std::ostringstream s;
    s.precision(4);
    s << "the widest passage between them narrows to clearance " << best << " m near (" << where.x() << ", "
      << where.y() << ")";
    return s.str();
  }

  /// String pulling: a forward greedy pass, then from each kept point the farthest one it sees,
  /// then tighten.
  std::vector<Eigen::Vector3d> shortcut(const std::vector<Eigen::Vector3d>& w, double radius) const {
    std::vector<Eigen::Vector3d> greedy{w.front()};
    for (std::size_t i = 0; i + 1 < w.size();) {
      std::size_t j = i + 1;
      while (j + 1 < w.size() && clear(w[i], w[j + 1], radius)) ++j;
      greedy.push_back(w[j]);
      i = j;
    }
    std::vector<Eigen::Vector3d> out{greedy.front()};
    for (std::size_t i = 0; i + 1 < greedy.size();) {
      std::size_t j = greedy.size() - 1;
      while (j > i + 1 && !clear(greedy[i], greedy[j], radius)) --j;
      out.push_back(greedy[j]);
      i = j;
    }
    return tighten(out, radius);
  }

  /// Corner sliding: each inner waypoint moves toward the midpoint of its neighbours' chord, as far
  /// (1, 1/2, ... 1/16 of the way) as both its segments stay clear; a waypoint whose neighbours see
  /// each other goes. Every move shortens the path (|a - q| + |q - b| is convex in q and least on
  /// the chord). A few sweeps take the string-pulled path most of the way to the taut one round the
  /// same obstacles.
  std::vector<Eigen::Vector3d> tighten(std::vector<Eigen::Vector3d> w, double radius) const {
    for (int sweep = 0; sweep < 12 && w.size() > 2; ++sweep) {
      double gained = 0;
      for (std::size_t i = 1; i + 1 < w.size(); ++i) {
        const Eigen::Vector3d &a = w[i - 1], &b = w[i + 1];
        if (clear(a, b, radius)) {
          gained += (w[i] - a).norm() + (b - w[i]).norm() - (b - a).norm();
          w.erase(w.begin() + static_cast<std::ptrdiff_t>(i));
          --i;
          continue;
        }
        const Eigen::Vector3d target = 0.5 * (a + b);
        for (double t = 1.0; t >= 1.0 / 16; t *= 0.5) {
          const Eigen::Vector3d q = w[i] + t * (target - w[i]);
          if (clear(a, q, radius) && clear(q, b, radius)) {
            gained += (w[i] - a).norm() + (b - w[i]).norm() - (q - a).norm() - (b - q).norm();
            w[i] = q;
            break;
          }
        }
      }
      if (gained < 1e-4) break;
    }
    return w;
  }
};

PathPlanner::PathPlanner(const std::vector<hulls::Obstacle>& obstacles, Roadmap roadmap,
                         std::vector<collision::Surface> surfaces)
    : impl_(std::make_unique<Impl>(obstacles, std::move(roadmap), std::move(surfaces))) {}
PathPlanner::~PathPlanner() = default;
PathPlanner::PathPlanner(PathPlanner&&) noexcept = default;
PathPlanner& PathPlanner::operator=(PathPlanner&&) noexcept = default;
const Roadmap& PathPlanner::roadmap() const { return impl_->roadmap; }
const collision::HullChecker& PathPlanner::checker() const { return impl_->checker; }
const PathPlanner::Graph& PathPlanner::graph() const { return impl_->graph; }
std::vector<std::pair<int, double>> PathPlanner::connections(const Eigen::Vector3d& end, double z,
                                                             double radius) const {
  return impl_->connect(end, z, radius, radius + impl_->roadmap.tolerance);
}

PlanResult PathPlanner::plan(const PlanRequest& request) const {
  const double r = request.radius;
  if (!(r >= 0) || !std::isfinite(r)) throw Error::inParameter("radius", "must be >= 0 and finite");
  if (!request.start.allFinite() || !request.goal.allFinite()) throw Error::inParameter("start/goal", "must be finite");
  const double z = request.flight_z.value_or(request.start.z());
  if (!std::isfinite(z)) throw Error::inParameter("flight_z", "must be finite");

  PlanResult result;
  auto blockedAt = [&](const char* which, const Eigen::Vector3d& p) {
    const collision::SegmentCheck c = impl_->checker.check({p, p}, r);
    if (!c.collides) return false;
    std::ostringstream s;
    s << which << " " << detail::pointText(p) << " is inside " << hitName(c) << " or within the radius " << r
      << " m of it";
    result.blocked = s.str();
    return true;
  };
  if (blockedAt("start", request.start) || blockedAt("goal", request.goal)) return result;

  std::vector<std::vector<Eigen::Vector3d>> routes;
  if (impl_->clear(request.start, request.goal, r)) {
    routes.push_back({request.start, request.goal});
  } else {
    const double floor = r + impl_->roadmap.tolerance;
    const auto from = impl_->connect(request.start, z, r, floor);
    const auto to = impl_->connect(request.goal, z, r, floor);
    std::ostringstream s;
    s.precision(6);
    if (from.empty() || to.empty()) {
      s << (from.empty() ? "start " + detail::pointText(request.start) : "goal " + detail::pointText(request.goal))
        << " sees no roadmap point with clearance " << r << " m at flight height " << z;
      result.blocked = s.str();
      return result;
    }
    auto chain = impl_->search(from, to, request.goal.head<2>(), floor);
    if (!chain) {
      const std::string where = impl_->narrowest(from, to);
      s << "no passage of clearance " << r << " m from start " << detail::pointText(request.start) << " to goal "
        << detail::pointText(request.goal) << ": " << (where.empty() ? "the roadmap does not join them" : where);
      result.blocked = s.str();
      return result;
    }
    // A* picks the route by its length along the Voronoi edges; once pulled taut another route
    // round the obstacles may be shorter, so a few alternatives are shortened too.
    std::vector<char> used(impl_->graph.position.size(), 0);
    for (int route = 0; route < kRoutes && chain; ++route) {
      std::vector<Eigen::Vector3d> w{request.start};
      for (const int v : *chain) {
        w.push_back(lift(impl_->graph.position[v], z));
        used[v] = 1;
      }
      w.push_back(request.goal);
      routes.push_back(std::move(w));
      if (route + 1 < kRoutes) {
        auto next = impl_->search(from, to, request.goal.head<2>(), floor, used);
        chain = next && *next != *chain ? std::move(next) : std::nullopt;
      }
    }
  }

  // The exact check has the last word: the shortest shortened route that passes it, else the
  // first roadmap route itself.
  const auto lengthOf = [](const std::vector<Eigen::Vector3d>& w) {
    double length = 0;
    for (std::size_t k = 1; k < w.size(); ++k) length += (w[k] - w[k - 1]).norm();
    return length;
  };
  std::vector<std::vector<Eigen::Vector3d>> candidates;
  for (const auto& w : routes) candidates.push_back(impl_->shortcut(w, r));
  std::sort(candidates.begin(), candidates.end(),
            [&](const auto& a, const auto& b) { return lengthOf(a) < lengthOf(b); });
  candidates.push_back(routes.front());
  for (const auto& candidate : candidates) {
    const collision::PathCheck check = impl_->checker.checkPath(candidate, r);
    if (check.first_colliding_segment) continue;
    result.path = candidate;
    result.length = lengthOf(candidate);
    return result;
  }
  result.blocked = "the roadmap path fails the exact hull check (roadmap built for another band or obstacles?)";
  return result;
}

RoadmapParams roadmapParamsFor(const std::vector<hulls::Obstacle>& obstacles,
                               const std::vector<Eigen::Vector3d>& points, double radius) {
  if (points.empty()) throw Error::inParameter("points", "empty: the roadmap's bounds and band come from them");
  RoadmapParams params;
  Eigen::Vector3d lo = points.front(), hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  params.z0 = lo.z() - radius;
  params.z1 = hi.z() + radius;
  Eigen::Vector2d lo2 = lo.head<2>(), hi2 = hi.head<2>();
  for (const auto& o : obstacles)
    for (const auto& p : o.footprint.polygon) {
      lo2 = lo2.cwiseMin(p);
      hi2 = hi2.cwiseMax(p);
    }
  const double margin = std::max(params.margin, 2 * radius + 0.5);
  params.bounds = Bounds2d{lo2.x() - margin, lo2.y() - margin, hi2.x() + margin, hi2.y() + margin};
  return params;
}

PlanResult planPath(const std::vector<hulls::Obstacle>& obstacles, const PlanRequest& request,
                    std::optional<RoadmapParams> roadmap_params, const std::vector<collision::Surface>& surfaces) {
  const double z = request.flight_z.value_or(request.start.z());
  const RoadmapParams params = roadmap_params.value_or(roadmapParamsFor(
      obstacles, {request.start, request.goal, Eigen::Vector3d(request.start.x(), request.start.y(), z)},
      request.radius));
  const PathPlanner planner(obstacles, buildRoadmap(obstacles, params, surfaces), surfaces);
  return planner.plan(request);
}

std::string hitName(const collision::SegmentCheck& check) {
  if (!check.surface.empty()) return "the " + check.surface;
  return "obstacle " + std::to_string(check.obstacle);
}

}  // namespace hullmap::planning
