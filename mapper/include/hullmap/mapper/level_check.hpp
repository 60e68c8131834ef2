#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/mapper/readers.hpp"

namespace hullmap::mapper {

/// Settings of fitFloorPlane's RANSAC. Deterministic: the same points and seed give the same plane.
struct PlaneFitParams {
  double inlier_distance = 0.1;    ///< map units; a point within this of the plane supports it
  double max_tilt_deg = 45.0;      ///< only planes whose normal is within this of +z are candidates
  std::size_t max_sample = 20000;  ///< points drawn (without replacement) when there are more
  int iterations = 300;            ///< random 3-point hypotheses tried
  std::uint32_t seed = 1;
};

/// A plane n·x = offset (n a unit vector with n.z >= 0), and the support that chose it.
struct PlaneFit {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  std::size_t inliers = 0;  ///< sampled points within inlier_distance
  std::size_t sampled = 0;  ///< points the fit looked at
  double tilt_deg = 0.0;    ///< angle between the normal and +z, degrees
};

/// The best-supported near-horizontal plane (a floor or a ceiling) of `points` (z-up map frame):
/// RANSAC over 3-point hypotheses whose normal is within max_tilt_deg of +z, then a least-squares
/// refit of the winner's inliers. nullopt for fewer than 3 points or when no hypothesis qualifies.
std::optional<PlaneFit> fitFloorPlane(const std::vector<Eigen::Vector3d>& points, const PlaneFitParams& params = {});

/// Share of the points a plane must hold to count as the map's floor for levelWarning.
inline constexpr double kFloorMinShare = 0.1;
/// Tilt of the floor plane, degrees, above which levelWarning speaks.
inline constexpr double kFloorMaxTiltDeg = 10.0;

/// One line when the map's main near-horizontal plane (holding at least kFloorMinShare of the
/// points) is tilted more than kFloorMaxTiltDeg from level after the frame change ("the main
/// floor-like plane ... is 21.3 degrees from level ..."), else nullopt. `points` are in the map
/// frame (occupied voxel centres do), `resolution` sets the inlier distance, `up` is the --up given.
std::optional<std::string> levelWarning(const std::vector<Eigen::Vector3d>& points, double resolution,
                                        const std::string& up);

/// True when `input` is recognisably an ORB-SLAM map: an echo dump, or a file whose name ORB-SLAM's
/// savers use or mention it (MapPoints, KeyFrame, orbslam, orb_slam, case-insensitive).
bool looksLikeOrbSlam(const InputStats& input);

/// One line saying that ORB-SLAM maps are in the camera frame (y down), so they likely need
/// --up -y, when an input looksLikeOrbSlam and `up_given` is false; else nullopt.
std::optional<std::string> orbSlamUpHint(const std::vector<InputStats>& inputs, bool up_given);

}  // namespace hullmap::mapper
