#include "hullmap/planning/fleet.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <sstream>
#include <string>
#include <unordered_map>

#include "hullmap/core/constants.hpp"
#include "hullmap/core/error.hpp"
#include "point_text.hpp"

namespace hullmap::planning {
namespace {

/// Smallest |p(s) - q(s)| for s in [0, 1], p and q moving linearly from pa to pb and qa to qb.
double closestApproach(const Eigen::Vector3d& pa, const Eigen::Vector3d& pb, const Eigen::Vector3d& qa,
                       const Eigen::Vector3d& qb) {
  const Eigen::Vector3d d0 = pa - qa;
  const Eigen::Vector3d dv = (pb - pa) - (qb - qa);
  const double vv = dv.squaredNorm();
  const double s = vv > 0 ? std::clamp(-d0.dot(dv) / vv, 0.0, 1.0) : 0.0;
  return (d0 + s * dv).norm();
}

/// Positions per time step of the drones planned so far; after its last step a drone stays put.
struct Reservations {
  std::vector<std::vector<Eigen::Vector3d>> steps;
  const Eigen::Vector3d& at(std::size_t drone, std::size_t t) const {
    const auto& s = steps[drone];
    return s[std::min(t, s.size() - 1)];
  }
  std::size_t horizon() const {
    std::size_t h = 0;
    for (const auto& s : steps) h = std::max(h, s.size());
    return h;
  }
  /// The motion a -> b over steps [t, t + k] keeps `separation` from every reserved drone.
  bool moveIsFree(const Eigen::Vector3d& a, const Eigen::Vector3d& b, std::size_t t, std::size_t k,
                  double separation) const {
    for (std::size_t s = 0; s < k; ++s) {
      const Eigen::Vector3d pa = a + (b - a) * (static_cast<double>(s) / k);
      const Eigen::Vector3d pb = a + (b - a) * (static_cast<double>(s + 1) / k);
      for (std::size_t j = 0; j < steps.size(); ++j)
        if (closestApproach(pa, pb, at(j, t + s), at(j, t + s + 1)) < separation) return false;
    }
    return true;
  }
  /// Staying at p from step t on keeps `separation` from every reserved drone for ever.
  bool stayIsFree(const Eigen::Vector3d& p, std::size_t t, double separation) const {
    for (std::size_t j = 0; j < steps.size(); ++j)
      for (std::size_t u = t; u + 1 < std::max(steps[j].size(), t + 2); ++u)
        if (closestApproach(p, p, at(j, u), at(j, u + 1)) < separation) return false;
    return true;
  }
};

struct Link {
  int to;
  std::size_t steps;
};

/// Steps from each vertex to the goal (index kGoal = graph size + 1) ignoring the other drones: a
/// reverse Dijkstra from the goal's links over the roadmap links that keep `floor` clearance (links
/// are symmetric), then the start (kGoal - 1) from its own links. kInf where the goal is out of reach.
template <typename StepsFor>
std::vector<double> stepsToGoal(const PathPlanner::Graph& graph, const std::vector<Link>& start_links,
                                const std::unordered_map<int, std::size_t>& goal_links, double floor,
                                const StepsFor& stepsFor) {
  const int vertices = static_cast<int>(graph.position.size());
  const int kStart = vertices, kGoal = vertices + 1;
  std::vector<double> h(vertices + 2, kInf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  h[kGoal] = 0;
  for (const auto& [v, k] : goal_links) {
    h[v] = std::min(h[v], static_cast<double>(k));
    open.emplace(h[v], v);
  }
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > h[v]) continue;
    for (const auto& l : graph.links[v])
      if (l.clearance >= floor && d + stepsFor(l.length) < h[l.to]) {
        h[l.to] = d + static_cast<double>(stepsFor(l.length));
        open.emplace(h[l.to], l.to);
      }
  }
  for (const auto& l : start_links) h[kStart] = std::min(h[kStart], l.steps + h[l.to]);
  return h;
}

/// The positions step by step along `chain` ((vertex, arrival step) from the start), moving at a
/// constant velocity between consecutive vertices.
template <typename Position>
std::vector<Eigen::Vector3d> perStepPositions(const std::vector<std::pair<int, std::size_t>>& chain,
                                              const Position& position) {
  std::vector<Eigen::Vector3d> steps{position(chain.front().first)};
  for (std::size_t c = 1; c < chain.size(); ++c) {
    const Eigen::Vector3d a = position(chain[c - 1].first), b = position(chain[c].first);
    const std::size_t k = chain[c].second - chain[c - 1].second;
    for (std::size_t s = 1; s <= k; ++s) steps.push_back(a + (b - a) * (static_cast<double>(s) / k));
  }
  return steps;
}

/// The timed path of per-step positions: the points that constant-velocity motion passes anyway
/// (the middle of three collinear, equally spaced steps) left out.
TimedPath timedPath(const std::vector<Eigen::Vector3d>& steps, double time_step) {
  TimedPath path;
  for (std::size_t s = 0; s < steps.size(); ++s) {
    const bool keep = s == 0 || s + 1 == steps.size() || (steps[s - 1] + steps[s + 1] - 2 * steps[s]).norm() > 1e-9;
    if (keep) path.push_back({static_cast<double>(s) * time_step, steps[s]});
  }
  return path;
}

/// Why `task` cannot start or end where it asks (its start or goal inside an obstacle, the floor or
/// the ceiling, or within the radius of one), or nullopt.
std::optional<std::string> blockedEnd(const PathPlanner& planner, const FleetTask& task, double radius) {
  for (const auto* end : {&task.start, &task.goal}) {
    const auto c = planner.checker().check({*end, *end}, radius);
    if (c.collides)
      return (end == &task.start ? "start " : "goal ") + detail::pointText(*end) + " is inside " + hitName(c) +
             " or within the radius of it";
  }
  return std::nullopt;
}

/// The (vertex, arrival step) chain from the start to the state `last` through `parent` (state keys
/// t * states + v; the start is its own parent).
std::vector<std::pair<int, std::size_t>> chainTo(std::uint64_t last,
                                                 const std::unordered_map<std::uint64_t, std::uint64_t>& parent,
                                                 std::uint64_t states) {
  std::vector<std::pair<int, std::size_t>> chain;
  for (std::uint64_t k = last;; k = parent.at(k)) {
    chain.emplace_back(static_cast<int>(k % states), static_cast<std::size_t>(k / states));
    if (parent.at(k) == k) break;
  }
  std::reverse(chain.begin(), chain.end());
  return chain;
}

/// The distinct consecutive points of `steps`, at least two (a drone that stays: its point twice):
/// the path the exact hull check takes.
std::vector<Eigen::Vector3d> visitedPoints(const std::vector<Eigen::Vector3d>& steps) {
  std::vector<Eigen::Vector3d> visited{steps.front()};
  for (const auto& p : steps)
    if ((p - visited.back()).norm() > 0) visited.push_back(p);
  if (visited.size() == 1) visited.push_back(visited.front());
  return visited;
}

std::string noScheduleReason(std::size_t horizon, double time_step) {
  std::ostringstream why;
  why << "no conflict-free schedule within " << horizon << " steps of " << time_step
      << " s (higher-priority drones block the way)";
  return why.str();
}

}  // namespace

Eigen::Vector3d positionAt(const TimedPath& path, double t) {
  if (path.empty()) throw Error::inParameter("path", "empty");
  if (t <= path.front().t) return path.front().position;
  for (std::size_t k = 1; k < path.size(); ++k)
    if (t <= path[k].t) {
      const double span = path[k].t - path[k - 1].t;
      const double s = span > 0 ? (t - path[k - 1].t) / span : 1.0;
      return path[k - 1].position + s * (path[k].position - path[k - 1].position);
    }
  return path.back().position;
}

double minimumSeparation(const std::vector<TimedPath>& paths) {
  double best = kInf;
  for (std::size_t i = 0; i < paths.size(); ++i)
    for (std::size_t j = i + 1; j < paths.size(); ++j) {
      std::vector<double> times;
      for (const auto& w : paths[i]) times.push_back(w.t);
      for (const auto& w : paths[j]) times.push_back(w.t);
      std::sort(times.begin(), times.end());
      times.erase(std::unique(times.begin(), times.end()), times.end());
      best = std::min(best, (positionAt(paths[i], times.front()) - positionAt(paths[j], times.front())).norm());
      for (std::size_t k = 1; k < times.size(); ++k)
        best = std::min(best, closestApproach(positionAt(paths[i], times[k - 1]), positionAt(paths[i], times[k]),
                                              positionAt(paths[j], times[k - 1]), positionAt(paths[j], times[k])));
    }
  return best;
}

FleetResult planFleet(const PathPlanner& planner, const std::vector<FleetTask>& tasks, const FleetParams& params) {
  if (!(params.radius > 0) || !std::isfinite(params.radius))
    throw Error::inParameter("radius", "must be > 0 and finite");
  if (!(params.speed > 0) || !std::isfinite(params.speed)) throw Error::inParameter("speed", "must be > 0 and finite");
  if (!(params.time_step >= 0) || !std::isfinite(params.time_step))
    throw Error::inParameter("time_step", "must be >= 0 and finite");
  FleetResult result;
  result.time_step = params.time_step > 0 ? params.time_step : params.radius / (2 * params.speed);
  const double reach = params.speed * result.time_step;  // metres per step at most
  const double separation = 2 * params.radius + 1e-9;
  const double floor = params.radius + planner.roadmap().tolerance;
  const auto& graph = planner.graph();
  const int vertices = static_cast<int>(graph.position.size());
  const int kStart = vertices, kGoal = vertices + 1;
  auto stepsFor = [&](double length) {
    return std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(length / reach - 1e-9)));
  };

  Reservations reserved;
  std::vector<TimedPath> routed;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const FleetTask& task = tasks[i];
    const double z = task.start.z();
    auto unrouted = [&](const std::string& why) {
      result.paths.emplace_back();
      result.unrouted.push_back(i);
      result.reasons.push_back("drone " + std::to_string(i) + ": " + why);
      reserved.steps.push_back({task.start});
    };
    if (const auto why = blockedEnd(planner, task, params.radius)) {
      unrouted(*why);
      continue;
    }

    // This drone's graph: the roadmap lifted to its height, plus its start and goal.
    auto position = [&](int v) -> Eigen::Vector3d {
      if (v == kStart) return task.start;
      if (v == kGoal) return task.goal;
      return {graph.position[v].x(), graph.position[v].y(), z};
    };
    std::vector<Link> start_links;
    std::unordered_map<int, std::size_t> goal_links;
    if (!planner.checker().check({task.start, task.goal}, params.radius).collides)
      start_links.push_back({kGoal, stepsFor((task.goal - task.start).norm())});
    for (const auto& [v, len] : planner.connections(task.start, z, params.radius))
      start_links.push_back({v, stepsFor(len)});
    for (const auto& [v, len] : planner.connections(task.goal, z, params.radius)) goal_links[v] = stepsFor(len);
    auto links = [&](int v) {
      std::vector<Link> out;
      if (v == kStart) return start_links;
      if (v == kGoal) return out;
      for (const auto& l : graph.links[v])
        if (l.clearance >= floor) out.push_back({l.to, stepsFor(l.length)});
      const auto g = goal_links.find(v);
      if (g != goal_links.end()) out.push_back({kGoal, g->second});
      return out;
    };

    // Heuristic: steps to the goal ignoring the other drones.
    const std::vector<double> h = stepsToGoal(graph, start_links, goal_links, floor, stepsFor);
    if (h[kStart] == kInf) {
      unrouted(start_links.empty() ? "start " + detail::pointText(task.start) + " sees no roadmap point with clearance"
                                   : "no passage of the radius's clearance from start to goal on the roadmap");
      continue;
    }

    // Space-time A*: states (vertex, step), moves along links or waits of one step.
    const std::size_t horizon = reserved.horizon() + 4 * static_cast<std::size_t>(h[kStart]) + 200;
    auto key = [&](int v, std::size_t t) { return static_cast<std::uint64_t>(t) * (vertices + 2) + v; };
    std::unordered_map<std::uint64_t, std::uint64_t> parent;
    using State = std::pair<double, std::pair<std::size_t, int>>;  // f, (t, v)
    std::priority_queue<State, std::vector<State>, std::greater<>> open;
    parent[key(kStart, 0)] = key(kStart, 0);
    open.push({h[kStart], {0, kStart}});
    std::size_t expansions = 0;
    std::optional<std::pair<int, std::size_t>> reached;
    while (!open.empty() && expansions < params.max_expansions) {
      // Named copies rather than a structured binding: C++17 lambdas (push, below) cannot capture one.
      const std::size_t t = open.top().second.first;
      const int v = open.top().second.second;
      open.pop();
      ++expansions;
      if (v == kGoal) {
        if (reserved.stayIsFree(task.goal, t, separation)) {
          reached = {v, t};
          break;
        }
      }
      auto push = [&](int w, std::size_t k) {
        const std::size_t arrive = t + k;
        if (arrive > horizon || parent.count(key(w, arrive))) return;
        if (!reserved.moveIsFree(position(v), position(w), t, k, separation)) return;
        parent[key(w, arrive)] = key(v, t);
        open.push({static_cast<double>(arrive) + h[w], {arrive, w}});
      };
      push(v, 1);  // wait
      for (const auto& l : links(v)) push(l.to, l.steps);
    }
    if (!reached) {
      unrouted(noScheduleReason(horizon, result.time_step));
      continue;
    }

    // Back to per-step positions, then drop the points that constant-velocity motion passes anyway.
    const auto chain = chainTo(key(reached->first, reached->second), parent, static_cast<std::uint64_t>(vertices + 2));
    std::vector<Eigen::Vector3d> steps = perStepPositions(chain, position);
    if (planner.checker().checkPath(visitedPoints(steps), params.radius).first_colliding_segment) {
      unrouted("the roadmap path fails the exact hull check (roadmap built for another band?)");
      continue;
    }
    TimedPath path = timedPath(steps, result.time_step);
    reserved.steps.push_back(std::move(steps));
    routed.push_back(path);
    result.paths.emplace_back(std::move(path));
  }
  result.min_separation = minimumSeparation(routed);
  return result;
}

}  // namespace hullmap::planning
