#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "hullmap/mapper/point_cloud.hpp"
#include "hullmap/mapper/readers.hpp"

namespace hullmap::mapper {

/// How a reference trajectory (`--align REF`) is written.
/// - kTum: `t x y z [qx qy qz qw]`, metres, z up (4 or 8 numbers a line; the orientation, when
///   present, is read and not used);
/// - kGps: `t lat lon alt`: WGS84 latitude and longitude in degrees, altitude in metres above the
///   ellipsoid; converted to local east-north-up metres around the first fix (x east, y north, z up).
/// Both: one pose a line, numbers separated by spaces, tabs or commas, `#` comments and blank lines;
/// timestamps above kNanosecondStampThreshold are nanoseconds and converted to seconds.
enum class ReferenceFormat { kTum, kGps };

/// "tum" or "gps" (case-insensitive). Throws hullmap::Error naming --align-format.
ReferenceFormat parseReferenceFormat(const std::string& text);
std::string toString(ReferenceFormat format);

/// One pose of a reference trajectory: a timestamp (seconds) and a metric position, z up.
struct ReferencePose {
  double stamp = 0.0;                                  ///< seconds
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< metres, z up
};

/// What parseReferenceTrajectory left out of a GPS log: lines without a fix, by reason.
struct ReferenceStats {
  /// "no_fix": latitude = longitude = 0 (what receivers write before their first fix);
  /// "non_finite": a NaN or infinite stamp, latitude, longitude or altitude;
  /// "out_of_range": a latitude outside [-90, 90] or a longitude outside [-180, 360] degrees.
  /// A reason appears only when it dropped a line.
  std::map<std::string, std::size_t> dropped;
};

/// Parses a reference trajectory (see ReferenceFormat). A line with the wrong count of numbers is an
/// Error "<name>:<line>: ...", as is (TUM) a non-finite value. A GPS line without a fix is dropped
/// and counted in `*stats` when given (see ReferenceStats); the ENU origin is the first valid fix.
/// An empty trajectory is returned as such (alignTrajectory refuses it).
std::vector<ReferencePose> parseReferenceTrajectory(std::string_view bytes, const std::string& name,
                                                    ReferenceFormat format, ReferenceStats* stats = nullptr);

/// Reads a reference trajectory file (see parseReferenceTrajectory). Throws hullmap::Error naming the
/// file when it cannot be read.
std::vector<ReferencePose> readReferenceTrajectory(const std::string& path, ReferenceFormat format,
                                                   ReferenceStats* stats = nullptr);

/// WGS84 geodetic (latitude, longitude in degrees, altitude in metres above the ellipsoid) to
/// Earth-centred Earth-fixed metres.
Eigen::Vector3d geodeticToEcef(double latitude_deg, double longitude_deg, double altitude_m);

/// WGS84 geodetic to local east-north-up metres around `origin` (latitude deg, longitude deg,
/// altitude m): the ECEF difference rotated into the tangent frame at the origin.
Eigen::Vector3d geodeticToEnu(const Eigen::Vector3d& geodetic, const Eigen::Vector3d& origin);

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
  Similarity transform;         ///< keyframe (map) frame -> reference frame
  double rmse = 0.0;            ///< metres: RMS distance between transformed keyframes and their matches
  double max_error = 0.0;       ///< metres: the largest of those distances
  std::size_t matched = 0;      ///< keyframes with a reference pose within the tolerance
  std::size_t unmatched = 0;    ///< keyframes without one
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
Alignment alignTrajectory(const std::vector<Keyframe>& keyframes, const std::vector<ReferencePose>& reference,
                          const AlignParams& params = {});

/// Applies the similarity to points in place (map units -> reference metres).
void applySimilarity(const Similarity& s, Points& points);

/// Applies it to keyframe poses (camera-to-map): position -> s(position), orientation ->
/// rotation * orientation.
void applySimilarity(const Similarity& s, std::vector<Keyframe>& keyframes);

}  // namespace hullmap::mapper
