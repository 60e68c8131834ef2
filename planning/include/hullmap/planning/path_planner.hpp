#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/planning/roadmap.hpp"

namespace hullmap::planning {

/// One query: a drone of radius `radius` (metres) from `start` to `goal` (z-up map frame).
struct PlanRequest {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d goal = Eigen::Vector3d::Zero();
  double radius = 0.0;
  std::optional<double> flight_z;  ///< height of the roadmap part of the path; default start.z()
};

/// A path, or why there is none. `path` holds waypoints from start to goal, every segment of which
/// the exact hull checker (collision::HullChecker) found clear of every obstacle by `radius`.
struct PlanResult {
  std::optional<std::vector<Eigen::Vector3d>> path;
  double length = 0.0;  ///< of the path, metres
  std::string blocked;  ///< one line naming where it is blocked, when there is no path
};

/// Plans on a roadmap: connects start and goal to the nearest roadmap points they see with
/// clearance `radius` (straight segments, exact hull check), A* over length on the roadmap edges
/// whose clearance is at least radius + the roadmap's tolerance (and two alternative routes with
/// the vertices already used made dearer), then shortcuts each (string pulling,
/// then corner sliding toward each neighbours' chord) while the exact check keeps the capsule of
/// `radius` clear, keeps the shortest, and verifies the whole path with the hull checker before
/// returning it. The roadmap must have been built from the same obstacles in
/// a band covering the flight height ± radius (planPath does that). Thread-safe for concurrent
/// plan() calls after construction.
class PathPlanner {
 public:
  /// `surfaces` (floor, ceiling) are obstacles for every check, as in collision::HullChecker; the
  /// roadmap should have been built with them. Throws hullmap::Error on an invalid hull (naming its
  /// id) or surface.
  PathPlanner(const std::vector<hulls::Obstacle>& obstacles, Roadmap roadmap,
              std::vector<collision::Surface> surfaces = {});
  ~PathPlanner();
  PathPlanner(PathPlanner&&) noexcept;
  PathPlanner& operator=(PathPlanner&&) noexcept;

  /// Throws hullmap::Error naming the field at fault ("radius", "start/goal", "flight_z") on a
  /// negative or non-finite radius or a non-finite coordinate.
  PlanResult plan(const PlanRequest& request) const;

  const Roadmap& roadmap() const;
  const collision::HullChecker& checker() const;

  /// Graph vertices (see graph()) that `end` reaches by a straight segment to the vertex lifted to
  /// height `z` with clearance `radius` (exact hull check), nearest first, at most 6, with the
  /// segment's length. Only vertices with a link of clearance >= radius + tolerance are tried.
  std::vector<std::pair<int, double>> connections(const Eigen::Vector3d& end, double z, double radius) const;

  /// The roadmap's polylines as one graph: vertex positions (ground plane) and, per vertex, its
  /// neighbours with the length and clearance of the piece between them. Roadmap nodes come first.
  struct Graph {
    std::vector<Eigen::Vector2d> position;
    struct Link {
      int to;
      double length;
      double clearance;
    };
    std::vector<std::vector<Link>> links;
  };
  const Graph& graph() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Roadmap settings for flights through `points` (starts, goals, flight heights) at `radius`: band
/// from the lowest point's z less the radius to the highest's plus it; bounds around the footprints
/// and the points, grown by max(1 m, 2 radius + 0.5 m); no clearance floor (so that a blocked query
/// can name its narrowest passage). Throws hullmap::Error naming "points" when they are empty.
RoadmapParams roadmapParamsFor(const std::vector<hulls::Obstacle>& obstacles,
                               const std::vector<Eigen::Vector3d>& points, double radius);

/// Builds the roadmap (roadmapParamsFor the start, goal and flight height unless `roadmap_params`
/// is given) and plans, `surfaces` (floor, ceiling) being obstacles for both. Throws hullmap::Error
/// as buildRoadmap and plan do.
PlanResult planPath(const std::vector<hulls::Obstacle>& obstacles, const PlanRequest& request,
                    std::optional<RoadmapParams> roadmap_params = std::nullopt,
                    const std::vector<collision::Surface>& surfaces = {});

/// What a check's hit is, for messages: "obstacle 3" or "the floor".
std::string hitName(const collision::SegmentCheck& check);

}  // namespace hullmap::planning
