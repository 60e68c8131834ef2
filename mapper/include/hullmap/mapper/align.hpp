#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hullmap/io/point_cloud.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/io/reference_trajectory.hpp"

namespace hullmap::mapper {

/// A similarity transform p -> scale * rotation * p + translation.
struct Similarity {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< proper rotation (det = +1)
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator()(const Eigen::Vector3d& p) const { return scale * (rotation * p) + translation; }
};

/// second after first: p -> second(first(p)).
Similarity compose(const Similarity& second, const Similarity& first);

/// The similarity that undoes `s` (s.scale must be > 0).
Similarity inverse(const Similarity& s);

/// A rigid transform as a similarity of scale 1.
Similarity fromIsometry(const Eigen::Isometry3d& t);

/// The 4 x 4 homogeneous matrix [scale * rotation, translation; 0 0 0 1].
Eigen::Matrix4d toMatrix(const Similarity& s);

/// How keyframes are matched to a reference trajectory.
struct AlignParams {
  double stamp_tolerance = 0.02;  ///< seconds: a keyframe matches the nearest reference stamp within this
};

/// The fitted frame and how well it fits.
struct Alignment {
  Similarity transform;       ///< keyframe (map) frame -> reference frame
  double rmse = 0.0;          ///< metres: RMS distance between transformed keyframes and their matches
  double max_error = 0.0;     ///< metres: the largest of those distances
  std::size_t matched = 0;    ///< keyframes with a reference pose within the tolerance
  std::size_t unmatched = 0;  ///< keyframes without one
};

/// Fits the similarity from keyframe positions (any frame, any scale: a monocular SLAM map) to a
/// metric reference, by Umeyama's least-squares method (Eigen::umeyama, with scaling).
/// Each keyframe is matched to the reference pose nearest in time, when within
/// params.stamp_tolerance; the others are counted as unmatched. Several keyframes may match one
/// reference pose.
/// Throws hullmap::Error naming `align` when the tolerance is not finite and >= 0, fewer than 3
/// keyframes match, or the fit is degenerate: the matched keyframe positions, or their reference
/// positions, are coincident or collinear (their spread across the best line is below 1e-6 of their
/// spread along it), so the rotation about that line is undetermined.
/// Thread-safe (no shared state).
Alignment alignTrajectory(const std::vector<io::Keyframe>& keyframes, const std::vector<io::ReferencePose>& reference,
                          const AlignParams& params = {});

/// Applies the similarity to points in place (map units -> reference metres).
void applySimilarity(const Similarity& s, io::Points& points);

/// Applies it to keyframe poses (camera-to-map): position -> s(position), orientation ->
/// rotation * orientation.
void applySimilarity(const Similarity& s, std::vector<io::Keyframe>& keyframes);

}  // namespace hullmap::mapper
