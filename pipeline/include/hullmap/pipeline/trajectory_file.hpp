#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include "hullmap/io/readers.hpp"

namespace hullmap::pipeline {

/// Name of the keyframe trajectory write() puts in a build directory when the build had keyframes.
inline constexpr const char* kTrajectoryFile = "trajectory.txt";

/// Writes `keyframes` atomically as a TUM trajectory (`t tx ty tz qx qy qz qw` a line, after a
/// `#` header line): camera-to-map poses in the build's output frame (z-up map frame, map units),
/// stamps in seconds, numbers in the shortest text that reads back exactly, so
/// io::readTumTrajectory gives the same poses back. Throws hullmap::Error naming `path`.
void writeTumTrajectory(const std::filesystem::path& path, const std::vector<io::Keyframe>& keyframes);

/// The keyframes of a build directory (its trajectory.txt), or nullopt when the build had none (no
/// such file). Throws hullmap::Error "<file>:<line>: <what>" on a malformed file.
std::optional<std::vector<io::Keyframe>> readBuildTrajectory(const std::filesystem::path& build_dir);

}  // namespace hullmap::pipeline
