#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

/// Metric reference trajectories of the keyframes (`--align REF`): TUM positions, or GPS fixes
/// converted to local east-north-up metres. mapper::alignTrajectory fits the keyframes to them.
namespace hullmap::io {

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
  /// Lines dropped per reason ("no_fix": latitude = longitude = 0, "non_finite", "out_of_range":
  /// outside [-90, 90] / [-180, 360] degrees); a reason appears only when it dropped a line.
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

}  // namespace hullmap::io
