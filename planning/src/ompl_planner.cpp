#include "hullmap/planning/ompl_planner.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <utility>

#include <ompl/base/MotionValidator.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/objectives/StateCostIntegralObjective.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>

#include "hullmap/core/error.hpp"
#include "point_text.hpp"

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace hullmap::planning {
namespace {

Eigen::Vector3d toPoint(const ob::State* s) {
  const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
  return {v->values[0], v->values[1], v->values[2]};
}

/// A state is valid when the sphere of the radius at it touches no hull (exact distance).
class HullValidity : public ob::StateValidityChecker {
 public:
  HullValidity(const ob::SpaceInformationPtr& si, const collision::HullChecker& checker, double radius)
      : ob::StateValidityChecker(si), checker_(checker), radius_(radius) {
    specs_.clearanceComputationType = ob::StateValidityCheckerSpecs::EXACT;
  }
  bool isValid(const ob::State* s) const override {
    const Eigen::Vector3d p = toPoint(s);
    return !checker_.check({p, p}, radius_).collides;
  }
  /// Distance to the nearest hull less the radius; 0 when in contact.
  double clearance(const ob::State* s) const override {
    const Eigen::Vector3d p = toPoint(s);
    return checker_.check({p, p}, radius_).clearance;
  }

 private:
  const collision::HullChecker& checker_;
  double radius_;
};

/// The straight motion is valid when the capsule it sweeps touches no hull: one exact check, no
/// sampling along it.
class CapsuleMotionValidator : public ob::MotionValidator {
 public:
  CapsuleMotionValidator(const ob::SpaceInformationPtr& si, const collision::HullChecker& checker, double radius)
      : ob::MotionValidator(si), checker_(checker), radius_(radius) {}

  bool checkMotion(const ob::State* s1, const ob::State* s2) const override {
    const bool clear = !checker_.check({toPoint(s1), toPoint(s2)}, radius_).collides;
    clear ? ++valid_ : ++invalid_;
    return clear;
  }

  bool checkMotion(const ob::State* s1, const ob::State* s2, std::pair<ob::State*, double>& last_valid) const override {
    const collision::SegmentCheck c = checker_.check({toPoint(s1), toPoint(s2)}, radius_);
    if (!c.collides) {
      ++valid_;
      return true;
    }
    ++invalid_;
    // The reported contact lies at or after the true one; step back until the state is valid.
    double t = c.t;
    for (int k = 0; k < 60; ++k) {
      t *= 0.9;
      if (last_valid.first != nullptr) si_->getStateSpace()->interpolate(s1, s2, t, last_valid.first);
      if (last_valid.first == nullptr || si_->isValid(last_valid.first)) break;
    }
    last_valid.second = t;
    return false;
  }

 private:
  const collision::HullChecker& checker_;
  double radius_;
};

/// Each metre costs 1 + weight * scale / (scale + clearance): path length plus a penalty for
/// running close to the hulls. Never below the length, so the length stays an admissible heuristic.
class ClearanceLengthObjective : public ob::StateCostIntegralObjective {
 public:
  ClearanceLengthObjective(const ob::SpaceInformationPtr& si, double weight, double scale)
      : ob::StateCostIntegralObjective(si, false), weight_(weight), scale_(scale) {
    setCostToGoHeuristic(&ob::goalRegionCostToGo);
  }
  ob::Cost stateCost(const ob::State* s) const override {
    if (weight_ == 0) return ob::Cost(1.0);
    const double c = std::max(0.0, si_->getStateValidityChecker()->clearance(s));
    return ob::Cost(1.0 + weight_ * scale_ / (scale_ + c));
  }
  ob::Cost motionCostHeuristic(const ob::State* s1, const ob::State* s2) const override {
    return ob::Cost(si_->distance(s1, s2));
  }

 private:
  double weight_;
  double scale_;
};

bool inside(const Box3d& box, const Eigen::Vector3d& p) {
  return (p.array() >= box.min.array()).all() && (p.array() <= box.max.array()).all();
}

}  // namespace

Box3d omplBoxFor(const std::vector<hulls::Obstacle>& obstacles, const PlanRequest& request) {
  const double margin = std::max(1.0, 2 * request.radius + 0.5);
  Box3d box{request.start.cwiseMin(request.goal), request.start.cwiseMax(request.goal)};
  double ground = box.min.z();
  double top = box.max.z();
  bool any = false;
  for (const auto& o : obstacles) {
    box.min.head<2>() = box.min.head<2>().cwiseMin(o.aabb_min.head<2>());
    box.max.head<2>() = box.max.head<2>().cwiseMax(o.aabb_max.head<2>());
    ground = any ? std::min(ground, o.aabb_min.z()) : o.aabb_min.z();
    top = std::max(top, o.aabb_max.z());
    any = true;
  }
  box.min.head<2>().array() -= margin;
  box.max.head<2>().array() += margin;
  if (any) {
    box.min.z() = std::min(box.min.z(), ground + request.radius);
    box.max.z() = std::max(box.max.z(), top + margin);
  }
  return box;
}

OmplPlanResult planPathOmpl(const std::vector<hulls::Obstacle>& obstacles, const PlanRequest& request,
                            const OmplParams& params, const std::vector<collision::Surface>& surfaces) {
  if (!(params.time_limit > 0) || !std::isfinite(params.time_limit))
    throw Error::inParameter("time_limit", "must be > 0 and finite seconds");
  if (!(params.clearance_weight >= 0) || !std::isfinite(params.clearance_weight))
    throw Error::inParameter("clearance_weight", "must be >= 0 and finite");
  if (!(params.clearance_scale > 0) || !std::isfinite(params.clearance_scale))
    throw Error::inParameter("clearance_scale", "must be > 0 and finite");
  const double r = request.radius;
  if (!(r >= 0) || !std::isfinite(r)) throw Error::inParameter("radius", "must be >= 0 and finite");
  if (!request.start.allFinite() || !request.goal.allFinite()) throw Error::inParameter("start/goal", "must be finite");

  OmplPlanResult result;
  result.box = params.box.value_or(omplBoxFor(obstacles, request));
  const Box3d& box = result.box;
  if (!box.min.allFinite() || !box.max.allFinite() || !(box.max.array() > box.min.array()).all())
    throw Error::inParameter("box", "must be finite with max > min on every axis");

  const collision::HullChecker checker(obstacles, surfaces);
  for (const auto& [which, p] :
       {std::pair<const char*, Eigen::Vector3d>{"start", request.start}, {"goal", request.goal}}) {
    std::ostringstream s;
    s.precision(6);
    if (!inside(box, p)) {
      s << which << " " << detail::pointText(p) << " is outside the planning box " << detail::pointText(box.min)
        << " - " << detail::pointText(box.max);
      result.blocked = s.str();
      return result;
    }
    const collision::SegmentCheck c = checker.check({p, p}, r);
    if (c.collides) {
      s << which << " " << detail::pointText(p) << " is inside " << hitName(c) << " or within the radius " << r
        << " m of it";
      result.blocked = s.str();
      return result;
    }
  }

  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
  auto space = std::make_shared<ob::RealVectorStateSpace>(3);
  ob::RealVectorBounds bounds(3);
  for (int k = 0; k < 3; ++k) {
    bounds.setLow(k, box.min[k]);
    bounds.setHigh(k, box.max[k]);
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker(std::make_shared<HullValidity>(si, checker, r));
  if (params.motion_check == OmplMotionCheck::kExact)
    si->setMotionValidator(std::make_shared<CapsuleMotionValidator>(si, checker, r));
  si->setup();  // kDiscrete: setup installs OMPL's DiscreteMotionValidator at its default resolution

  ob::ScopedState<ob::RealVectorStateSpace> start(space), goal(space);
  for (int k = 0; k < 3; ++k) {
    start[k] = request.start[k];
    goal[k] = request.goal[k];
  }
  auto problem = std::make_shared<ob::ProblemDefinition>(si);
  problem->setStartAndGoalStates(start, goal);
  auto objective = std::make_shared<ClearanceLengthObjective>(si, params.clearance_weight, params.clearance_scale);
  problem->setOptimizationObjective(objective);

  auto planner = std::make_shared<og::RRTstar>(si);
  planner->setProblemDefinition(problem);
  planner->setup();
  planner->solve(ob::timedPlannerTerminationCondition(params.time_limit));

  if (!problem->hasExactSolution()) {
    std::ostringstream s;
    s << "RRT* found no path for radius " << r << " m from " << detail::pointText(request.start) << " to "
      << detail::pointText(request.goal) << " in " << params.time_limit << " s inside the box "
      << detail::pointText(box.min) << " - " << detail::pointText(box.max);
    result.blocked = s.str();
    return result;
  }
  const ob::PathPtr found = problem->getSolutionPath();
  auto& solution = *found->as<og::PathGeometric>();
  result.cost = solution.cost(objective).value();
  for (const ob::State* s : solution.getStates()) result.planner_path.push_back(toPoint(s));
  // OMPL's states are copies of start and goal; keep the caller's values bit for bit.
  result.planner_path.front() = request.start;
  result.planner_path.back() = request.goal;
  result.check = checker.checkPath(result.planner_path, r);
  if (result.check.first_colliding_segment) {
    std::ostringstream s;
    s << "RRT*'s path fails the exact hull check on segment " << *result.check.first_colliding_segment;
    result.blocked = s.str();
    return result;
  }
  result.path = result.planner_path;
  for (std::size_t k = 1; k < result.planner_path.size(); ++k)
    result.length += (result.planner_path[k] - result.planner_path[k - 1]).norm();
  return result;
}

}  // namespace hullmap::planning
