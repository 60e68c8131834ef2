#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "hullmap/io/point_cloud.hpp"

namespace hullmap::io {

/// The point formats hullmap reads. Recognised from content first, the extension second.
///
/// - kOrbSlamEcho: `rostopic echo /ORB_SLAM/Map > dump.txt` of ORB-SLAM (v1): a stream of
///   visualization_msgs/Marker messages separated by `---`. The map is the last marker of namespace
///   "MapPoints", id 0 (all points) plus the last of id 6 (reference points), type 8 (POINTS).
///   Markers of other namespaces (KeyFrames, Graph, Camera) are ignored; an incomplete last message
///   (a dump stopped with Ctrl-C) is ignored.
/// - kText: one point a line, numbers separated by spaces, tabs or commas (ORB-SLAM2/3 map-point
///   dumps, `.xyz`). An optional header line of words (`pos_x, pos_y, pos_z`), `#` comments and
///   blank lines are allowed. The first data line fixes the column count (at least 3); x y z are
///   the first three columns, the rest (normals, colours) are ignored; every line must have that count.
/// - kPcd: PCD v0.7, DATA ascii, binary or binary_compressed (LZF), any field layout with F4/F8
///   x y z fields (host byte order, i.e. little-endian).
/// - kPly: PLY 1.0 ascii, binary_little_endian or binary_big_endian; the x y z properties of the
///   `vertex` element (any scalar type); other properties and elements (faces, lists) are skipped.
enum class PointFormat { kOrbSlamEcho, kText, kPcd, kPly };

/// "orbslam_echo", "text", "pcd", "ply" (the InputStats::format names).
std::string toString(PointFormat format);

/// Guesses the format of `path` from its first bytes (and its extension when the file is empty).
/// Throws hullmap::Error when the file cannot be opened or holds binary data of no known format.
PointFormat detectPointFormat(const std::string& path);

/// The same, on bytes already in memory; `name` is used in messages only.
PointFormat detectPointFormat(std::string_view bytes, const std::string& name);

/// Receives the points of a streaming reader batch by batch, in file order (map units, the input's
/// own frame). A batch holds 1 to PointStreamParams::batch_points points (never 0); the consumer may
/// change it or move from it: the reader clears it afterwards. Called on the reader's thread; an
/// exception it throws ends the read and reaches the reader's caller.
using PointBatchConsumer = std::function<void(Points& batch)>;

/// How the streaming readers deliver points and read their files.
struct PointStreamParams {
  std::size_t batch_points = 65536;   ///< points per batch, >= 1 (SIZE_MAX: one batch per file)
  std::size_t read_bytes = 1u << 20;  ///< bytes asked of each read(2) on pipes and other non-regular files, >= 1
};

/// Parses the bytes of one point file of any supported format (detected from the content).
/// `name` (the path) is used in error messages and stored in InputStats::path. Points with a NaN or
/// infinite coordinate are dropped and counted under "non_finite". An empty input, or a file of a
/// known format holding no points, gives zero points (not an error). Throws hullmap::Error naming
/// `name` and the line (text formats) or the byte offset / point index (binary formats) on malformed
/// input, unknown formats and truncated data. Never allocates more than the input size justifies.
/// Thread-safe (no shared state).
PointSet parsePoints(std::string_view bytes, const std::string& name);

/// Reads one point file of any supported format (see parsePoints). Throws hullmap::Error naming the
/// file when it cannot be read. Thread-safe (no shared state).
PointSet readPointFile(const std::string& path);

/// Reads and unions several point files, in order; one InputStats per file.
PointSet readPointFiles(const std::vector<std::string>& paths);

/// Reads one point file as readPointFile does (same points in the same order, same InputStats,
/// same errors) but hands the points to `consume` in batches as it parses, without holding the
/// file or its points:
/// - a regular file is mapped and the pages already parsed are handed back to the kernel as the
///   parse moves on (madvise MADV_DONTNEED, 8 MiB at a time): about 8 MiB of it stays resident,
///   whatever its size; pipes and other non-regular files are read params.read_bytes at a time;
/// - text, PCD ascii and binary and PLY are parsed incrementally; PCD binary_compressed is one LZF
///   block holding the fields one after another, so it is decompressed whole, then delivered in
///   batches; an ORB-SLAM echo dump is loaded whole (the map is its last message of id 0 and of
///   id 6, known only at the end of the dump) and its points are delivered after the whole dump
///   has been parsed.
/// Points are in the input's frame, map units.
/// On an error the batches before it have already been delivered; the Error names the file and
/// line (or byte offset) as readPointFile's. Throws hullmap::Error when batch_points or read_bytes
/// is 0. Thread-safe (no shared state) when `consume` is.
InputStats streamPointFile(const std::string& path, const PointStreamParams& params, const PointBatchConsumer& consume);

/// streamPointFile on each file in order, one consumer for all (a batch never holds points of two
/// files); one InputStats per file.
std::vector<InputStats> streamPointFiles(const std::vector<std::string>& paths, const PointStreamParams& params,
                                         const PointBatchConsumer& consume);

/// parsePoints in batches (see streamPointFile): the same points, InputStats and errors.
InputStats streamPoints(std::string_view bytes, const std::string& name, const PointStreamParams& params,
                        const PointBatchConsumer& consume);

/// One keyframe pose of a TUM trajectory: camera-to-map transform, timestamp in seconds.
struct Keyframe {
  double stamp = 0.0;  ///< seconds (nanosecond stamps are converted)
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/// Stamps above this are taken as nanoseconds (1e12 s is 31 700 years; 1e12 ns is 17 minutes
/// after 1970, earlier than any real recording).
constexpr double kNanosecondStampThreshold = 1e12;

/// Parses a TUM trajectory `t tx ty tz qx qy qz qw`, one pose a line (spaces, tabs or commas),
/// `#` comments and blank lines. Timestamps above kNanosecondStampThreshold are taken as
/// nanoseconds and converted to seconds (ORB-SLAM3 writes `1403636579763555840.000000`).
/// Quaternions are normalised. A line without exactly 8 numbers, a non-finite value, or a zero
/// quaternion is an Error "<name>:<line>: ...".
std::vector<Keyframe> parseTumTrajectory(std::string_view bytes, const std::string& name);

/// Reads a TUM trajectory file (see parseTumTrajectory).
std::vector<Keyframe> readTumTrajectory(const std::string& path);

}  // namespace hullmap::io
