#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/io/readers.hpp"

namespace hullmap::mapper {

/// Share of the points a plane must hold to count as the map's floor for levelWarning.
inline constexpr double kFloorMinShare = 0.1;
/// Tilt of the floor plane, degrees, above which levelWarning speaks.
inline constexpr double kFloorMaxTiltDeg = 10.0;

/// One line when the map's floor (mapper::findBoundingPlane with band = `resolution`, tilt up to
/// 45 degrees, holding at least kFloorMinShare of the points, at most 10% of them under it) is tilted more than
/// kFloorMaxTiltDeg from level after the frame change ("the map's main floor-like plane ... is 21.3 degrees from level
/// ..."), else nullopt. `points` are in the map frame (occupied voxel centres do), `resolution` sets the inlier band,
/// `up` is the --up given.
std::optional<std::string> levelWarning(const std::vector<Eigen::Vector3d>& points, double resolution,
                                        const std::string& up);

/// True when `input` is recognisably an ORB-SLAM map: an echo dump, or a file whose name ORB-SLAM's
/// savers use or mention it (MapPoints, KeyFrame, orbslam, orb_slam, case-insensitive).
bool looksLikeOrbSlam(const io::InputStats& input);

/// One line saying that ORB-SLAM maps are in the camera frame (y down), so they likely need
/// --up -y, when an input looksLikeOrbSlam and `up_given` is false; else nullopt.
std::optional<std::string> orbSlamUpHint(const std::vector<io::InputStats>& inputs, bool up_given);

}  // namespace hullmap::mapper
