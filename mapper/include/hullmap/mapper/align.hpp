#pragma once

#include <cstddef>
#include <optional>
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

/// How the map is moved onto the reference.
enum class AlignModel {
  kAuto,        ///< kDrift when the map's scale drifts (see alignTrajectory), else kSimilarity
  kSimilarity,  ///< one similarity for the whole map
  kDrift,       ///< a scale and translation along the path (monocular scale drift), one rotation
};

/// "auto", "similarity" or "drift". Throws hullmap::Error naming `align_model`.
AlignModel parseAlignModel(const std::string& text);
const char* toString(AlignModel model);

/// How keyframes are matched to a reference trajectory.
struct AlignParams {
  double stamp_tolerance = 0.02;  ///< seconds: a keyframe matches the nearest reference stamp within this
  AlignModel model = AlignModel::kAuto;
};

/// Monocular scale drift undone along the path: at each anchor (a matched keyframe, in time order)
/// the similarity p -> scales[i] * rotation * p + translations[i], its scale and translation fitted
/// to the anchors within `half_window` of it in time order (rotation: the whole path's). A point is
/// moved by the blend of the similarities at the two ends of its nearest anchor segment (see
/// applyAlignment).
struct DriftCorrection {
  std::vector<double> stamps;                 ///< the anchors' keyframe stamps
  std::vector<Eigen::Vector3d> anchors;       ///< the anchors' positions, keyframe (input) frame
  std::vector<double> scales;                 ///< > 0
  std::vector<Eigen::Vector3d> translations;  ///< reference frame
  std::size_t half_window = 0;                ///< anchors each side in a local fit
  /// metres: RMS distance of each anchor's match from the fit of its window without it
  double holdout_rmse = 0.0;
};

/// The fitted frame and how well it fits.
struct Alignment {
  Similarity transform;                  ///< keyframe (map) frame -> reference frame: the whole path's best similarity
  std::optional<DriftCorrection> drift;  ///< set when the drift model moved the map (transform.rotation its rotation)
  double rmse = 0.0;                     ///< metres: RMS distance between the moved keyframes and their matches
  double max_error = 0.0;                ///< metres: the largest of those distances
  double similarity_rmse = 0.0;          ///< metres: the RMS distance with `transform` alone
  /// radians: the standard error the reference alone leaves in the roll about its path's main axis
  double roll_sigma = 0.0;
  bool roll_from_cameras = false;  ///< that roll was undetermined (> 1 degree) and the cameras set it
  double roll_turn = 0.0;          ///< radians: how far they turned it from the least-squares fit
  std::size_t matched = 0;         ///< keyframes with a reference pose within the tolerance
  std::size_t unmatched = 0;       ///< keyframes without one
};

/// The least anchors the drift model is fitted with, and the share of them each side of an anchor
/// in its local fit (at least 3).
inline constexpr std::size_t kDriftMinAnchors = 20;
inline constexpr double kDriftWindowShare = 0.05;

/// Fits the similarity from keyframe positions (any frame, any scale: a monocular SLAM map) to a
/// metric reference, by Umeyama's least-squares method (Eigen::umeyama, with scaling).
/// Each keyframe is matched to the reference pose nearest in time, when within
/// params.stamp_tolerance; the others are counted as unmatched. Several keyframes may match one
/// reference pose.
/// Roll: when a nearly straight reference leaves it undetermined, the cameras set it. Scale drift: with
/// at least kDriftMinAnchors matches a drift model is fitted too, taken by kAuto when it predicts
/// better (both rules: docs/DESIGN_NOTES.md, "align.hpp: roll and scale drift").
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

/// Moves points into the reference frame by the alignment: its similarity, or with `drift` each
/// point p by (1 - f) S_i(p) + f S_i+1(p), where [anchor i, anchor i+1] is the anchor segment nearest
/// p among those touching its 8 nearest anchors and f in [0, 1] the fraction of p's nearest point on
/// it (S_i: anchor i's similarity); exact at an anchor (p = anchor i gives S_i(p)). Continuous
/// along the path and across it where the nearest segments are neighbours; it jumps where the
/// nearest segment does (between two passes of a path that comes back). Parallel (TBB).
void applyAlignment(const Alignment& a, io::Points& points);

/// The same for keyframe poses: positions moved as points, orientations rotated by transform.rotation.
void applyAlignment(const Alignment& a, std::vector<io::Keyframe>& keyframes);

}  // namespace hullmap::mapper
