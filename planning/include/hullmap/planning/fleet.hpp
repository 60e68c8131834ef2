#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/planning/path_planner.hpp"

namespace hullmap::planning {

/// A drone's position at time t (seconds from the common start), z-up map frame, metres.
struct TimedWaypoint {
  double t = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

/// Piecewise-linear motion between the waypoints; before the first the drone is at the first,
/// after the last it stays at the last.
using TimedPath = std::vector<TimedWaypoint>;

/// One drone's task: fly from start to goal (the roadmap part at the start's height).
struct FleetTask {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d goal = Eigen::Vector3d::Zero();
};

/// Settings of planFleet.
struct FleetParams {
  double radius = 0.0;                   ///< every drone's radius, metres (> 0): 2 radius apart, radius from obstacles
  double speed = 1.0;                    ///< top speed, metres per second (> 0)
  double time_step = 0.0;                ///< seconds per step of the space-time search; 0: radius / (2 speed)
  std::size_t max_expansions = 2000000;  ///< space-time states expanded per drone before giving up
};

struct FleetResult {
  std::vector<std::optional<TimedPath>> paths;  ///< per task, in task order; nullopt: not routed
  std::vector<std::size_t> unrouted;            ///< indices of the tasks without a path
  std::vector<std::string> reasons;             ///< one line per unrouted task, same order
  double min_separation = 0.0;                  ///< exact smallest distance between two routed drones (inf if < 2)
  double time_step = 0.0;                       ///< the step used, seconds
};

/// Prioritized planning with reservations on the roadmap: drones in task order (earlier tasks
/// have priority), each by A* over (roadmap vertex, time step) with waits, avoiding every vertex
/// and edge conflict with the timed paths already planned: for each step the two drones' linear
/// motions are checked in closed form to keep 2 radius + 1e-9 apart, and a drone at its goal stays
/// there. A drone that cannot be routed stays at its start for the rest (later drones avoid it).
/// Each link of length L takes ceil(L / (speed time_step)) steps, so no drone exceeds `speed`.
/// Every routed path is checked by the planner's exact hull checker at `radius`. Not complete (no
/// prioritized planner is): a drone may be unrouted although another order would route it.
/// Throws hullmap::Error naming the parameter at fault.
FleetResult planFleet(const PathPlanner& planner, const std::vector<FleetTask>& tasks, const FleetParams& params);

/// Exact smallest distance between any two of the timed paths at any instant (piecewise-linear
/// motions, closed form per common time interval); +inf for fewer than two paths.
double minimumSeparation(const std::vector<TimedPath>& paths);

/// Position on a timed path at time t (clamped to its ends). Throws hullmap::Error naming "path" when empty.
Eigen::Vector3d positionAt(const TimedPath& path, double t);

}  // namespace hullmap::planning
