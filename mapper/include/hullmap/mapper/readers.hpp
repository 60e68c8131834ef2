#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hullmap/mapper/point_cloud.hpp"

namespace hullmap::mapper {

/// The point formats hullmap reads. Recognised from content first, the extension second.
enum class PointFormat { kOrbSlamEcho, kText, kPcd, kPly };

/// Guesses the format of `path` from its first bytes (and its extension when the content is plain
/// numbers). Throws hullmap::Error when the file cannot be opened.
PointFormat detectPointFormat(const std::string& path);

/// Reads one point file of any supported format. Non-finite points are dropped and counted under
/// "non_finite". Throws hullmap::Error naming file and line (or byte offset) on malformed input.
/// Thread-safe (no shared state).
PointSet readPointFile(const std::string& path);

/// Reads and unions several point files, in order; one InputStats per file.
PointSet readPointFiles(const std::vector<std::string>& paths);

/// One keyframe pose of a TUM trajectory: camera-to-map transform, timestamp in seconds.
struct Keyframe {
  double stamp = 0.0;  ///< seconds (nanosecond stamps are converted)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/// Reads a TUM trajectory `t tx ty tz qx qy qz qw`, one pose a line, `#` comments.
/// Timestamps above 1e12 are taken as nanoseconds. Quaternions are normalised; a zero or
/// non-finite one is an error naming the line.
std::vector<Keyframe> readTumTrajectory(const std::string& path);

}  // namespace hullmap::mapper
