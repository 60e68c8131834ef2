#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/planning/path_planner.hpp"

namespace hullmap::planning {

/// Axis-aligned box in the z-up map frame, metres.
struct Box3d {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
};

/// How OMPL decides that a straight motion between two states is free.
enum class OmplMotionCheck {
  /// hullmap's exact capsule sweep (collision::HullChecker::check of the segment at the radius):
  /// no obstacle, however thin, is skipped.
  kExact,
  /// OMPL's DiscreteMotionValidator (states every 1% of the box's diagonal, each checked exactly): it
  /// can step over thin obstacles; for bench/ only (docs/DESIGN_NOTES.md, "ompl_planner.hpp").
  kDiscrete,
};

/// Settings of planPathOmpl. Units: metres and seconds, z-up map frame.
struct OmplParams {
  double time_limit = 1.0;  ///< RRT* runs this long (it is anytime: it keeps improving), s, > 0
  /// Clearance weight, >= 0 (0: length only): a metre costs 1 + weight * scale / (scale + c), c the
  /// clearance (docs/DESIGN_NOTES.md, "ompl_planner.hpp: the objective").
  double clearance_weight = 0.5;
  double clearance_scale = 0.5;  ///< metres, > 0
  std::optional<Box3d> box;      ///< sampling box; default omplBoxFor
  OmplMotionCheck motion_check = OmplMotionCheck::kExact;
};

/// What planPathOmpl found.
struct OmplPlanResult {
  /// The planner's path when the exact hull check found every segment clear by the radius.
  std::optional<std::vector<Eigen::Vector3d>> path;
  double length = 0.0;  ///< of `path`, metres
  std::string blocked;  ///< one line saying why there is no path
  /// OMPL's exact solution as returned (empty: none in the time limit), checked below; it may collide
  /// only with OmplMotionCheck::kDiscrete (the check is repeated for kExact too).
  std::vector<Eigen::Vector3d> planner_path;
  collision::PathCheck check;
  double cost = 0.0;  ///< objective value of planner_path
  Box3d box;          ///< the sampling box used
};

/// The default sampling box: the obstacles' bounding boxes, start and goal, grown in x and y by
/// max(1 m, 2 radius + 0.5 m); in z from the lowest obstacle bottom (the ground, when obstacles
/// stand on it) plus the radius up to the highest top plus that margin, and always taking in the
/// start and goal.
Box3d omplBoxFor(const std::vector<hulls::Obstacle>& obstacles, const PlanRequest& request);

/// Plans in 3D with OMPL's RRT* (ompl::geometric::RRTstar, asymptotically optimal, default range
/// and rewiring) from request.start to request.goal inside the box, for a sphere of request.radius:
/// states are valid when the exact hull checker finds them clear by the radius; motions are checked
/// by `params.motion_check` (the exact capsule sweep by default); the objective is length plus the
/// clearance term above. The returned path is OMPL's, unsimplified, verified by
/// HullChecker::checkPath before it is returned. request.flight_z is ignored. Lowers OMPL's global
/// log level to warnings (OMPL would otherwise print its progress). Thread-compatible: OMPL's random
/// seed is process-wide, so results differ between runs.
/// Throws hullmap::Error naming the parameter at fault: time_limit not > 0 and finite,
/// clearance_weight < 0, clearance_scale <= 0, a negative radius, an empty box, non-finite
/// coordinates; and on an invalid hull (naming its id).
/// `surfaces` (floor, ceiling) are obstacles for the states, the motions and the final check.
OmplPlanResult planPathOmpl(const std::vector<hulls::Obstacle>& obstacles, const PlanRequest& request,
                            const OmplParams& params = {}, const std::vector<collision::Surface>& surfaces = {});

}  // namespace hullmap::planning
