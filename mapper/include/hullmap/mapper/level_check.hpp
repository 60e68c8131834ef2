#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/core/warning.hpp"
#include "hullmap/io/readers.hpp"

namespace hullmap::mapper {

/// Share of the points a plane must hold to count as the map's floor for levelWarning.
inline constexpr double kFloorMinShare = 0.1;
/// Tilt of the floor plane, degrees, above which levelWarning speaks.
inline constexpr double kFloorMaxTiltDeg = 10.0;

/// kMapLooksTilted when the map's floor (mapper::findBoundingPlane with band = `resolution`, tilt up
/// to 45 degrees, holding at least kFloorMinShare of the points, at most 10% of them under it) is
/// tilted more than kFloorMaxTiltDeg from level after the frame change (numbers inlier_share,
/// tilt_deg; subject `up`, the up axis given), else nullopt. `points` are in the map frame (occupied
/// voxel centres are), `resolution` sets the inlier band.
std::optional<Warning> levelWarning(const std::vector<Eigen::Vector3d>& points, double resolution,
                                    const std::string& up);

/// True when `input` is recognisably an ORB-SLAM map: an echo dump, or a file whose name ORB-SLAM's
/// savers use or mention it (MapPoints, KeyFrame, orbslam, orb_slam, case-insensitive).
bool looksLikeOrbSlam(const io::InputStats& input);

/// kOrbSlamFrame (subject: the input's path) when an input looksLikeOrbSlam and `up_given` is
/// false: ORB-SLAM maps are in the first camera's frame (y down), so they likely need up "-y".
std::optional<Warning> orbSlamUpHint(const std::vector<io::InputStats>& inputs, bool up_given);

}  // namespace hullmap::mapper
