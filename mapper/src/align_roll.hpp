#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "hullmap/mapper/align.hpp"

namespace hullmap::mapper {

/// The roll of a fitted similarity about the reference path's main axis, and where it came from.
struct RollFit {
  Similarity transform;       ///< the similarity, turned about that axis when from_cameras
  double sigma = 0.0;         ///< radians: the roll's standard error from the reference alone
  bool from_cameras = false;  ///< the reference left it undetermined and the cameras set it
  double turn = 0.0;          ///< radians: how far the cameras turned it, in (-pi, pi]
};

/// A reference path that is nearly a line (a straight street) pins the rotation about that line
/// only through its positions' spread across it: with per-axis noise e = rmse / sqrt(3) and the
/// spread's sum of squared distances from the line L, the roll's standard error is e / sqrt(L).
/// Above kRollSigmaMax the keyframes' own cameras set it instead: ORB-SLAM's camera x axis (right)
/// is level for a camera mounted without roll, whatever its pitch, so the roll that makes the
/// matched cameras' x axes most nearly horizontal (least sum of squared z components), of the two
/// that do, the one that turns their y axes (down) downward. Kept when the cameras do not pin it
/// either: their x axes along the line (least and largest sums within n / 4 of each other) or the
/// line more than 60 degrees from horizontal (then the roll is a heading the cameras cannot give).
/// `to`: the matched reference positions, `orientations` their keyframes' (camera to map), `s` the
/// fit of the keyframes to them with RMS residual `rmse`.
RollFit fitRoll(const std::vector<Eigen::Vector3d>& to, const std::vector<Eigen::Quaterniond>& orientations,
                const Similarity& s, double rmse);

/// radians: the largest standard error of the roll the reference alone may leave (1 degree).
inline constexpr double kRollSigmaMax = 0.017453292519943295;

}  // namespace hullmap::mapper
