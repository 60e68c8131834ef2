#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/core/warning.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/pipeline/build_params.hpp"
#include "hullmap/pipeline/build_result.hpp"
#include "hullmap/pipeline/output_dir.hpp"

/// The whole build of `hullmap build` as a library: point files (or points in memory, or one .bt/.ot)
/// -> map frame (a reference trajectory's, or an up axis and scale) -> floor found and levelled ->
/// filters -> OctoMap octree -> floor/ceiling voxels set aside -> eps/minPts chosen from the map ->
/// exact DBSCAN of the obstacle voxels -> convex obstacles split into convex parts, and the output
/// directory it writes. Everything in the z-up map frame, map units (metres for a
/// metric SLAM map). Functions are reentrant: two builds may run at once on different params; each
/// build uses all cores (TBB) in the caller's arena.
namespace hullmap::pipeline {

/// Clusters the map's occupied voxels (each weighted by its map points) with `dbscan` and wraps each
/// cluster in a convex obstacle (no floor, no parts). Throws hullmap::Error naming the parameter at fault.
ClusteredVoxels clusterMap(const mapper::OccupancyMap& map, const clustering::DbscanParams& dbscan);

/// Whether a build of `params` levels a floor it finds: level kOn yes, kOff no; kAuto when the
/// input is in a camera's frame: camera_frame when given, else an up axis other than z, or an input
/// or the trajectory recognisably ORB-SLAM's (mapper::looksLikeOrbSlam: an echo dump, or ORB-SLAM's
/// file names). Never with align or for an octree input. `inputs` are the inputs as read (their
/// formats known).
bool levelsMap(const BuildParams& params, const std::vector<io::InputStats>& inputs);

/// Runs read -> align or frame -> floor (level) -> filters -> octree -> surfaces -> auto eps/minPts
/// -> DBSCAN -> obstacles -> convex parts on params.inputs; each stage is timed in
/// report.timings_ms ("read", "align", "frame_and_filters", "floor", "octree", "surfaces",
/// "auto_params", "dbscan", "obstacles", "convex_parts"). Point files without trajectory and origin
/// are streamed batch by batch (never whole in memory; the timings of read, frame_and_filters and
/// octree are then each summed over the batches): the floor is then searched on a sample of the
/// points kept while streaming (every k-th point, k chosen from the file sizes), and when it must
/// be levelled the files are streamed a second time. Throws hullmap::Error naming the file (and
/// line) or the parameter at fault (parameter names are BuildParams' fields: "scale",
/// "crop/z_min/z_max", "trajectory/origin", "align", "eps", "min_pts", "concavity").
BuildResult build(const BuildParams& params);

/// The same build from points already in memory, input frame (a live node has no file): `points`
/// go through params.frame, params.filters, the octree (with params.trajectory or params.origin as
/// for files) and clustering; params.inputs is ignored and the report lists one input named
/// `name` with format "memory". Throws hullmap::Error as build().
BuildResult buildFromPoints(io::Points points, const BuildParams& params, const std::string& name = "points");

/// The same with keyframe poses in memory (input frame, camera-to-map, as a bag or a live topic gives
/// them) when `keyframes` holds a value: free space is ray-cast from them exactly as from a
/// params.trajectory file with the same poses, and the result's params.trajectory (report.json's
/// "trajectory") is `keyframes_name`. params.trajectory must then be unset. Throws hullmap::Error
/// as build(), "<keyframes_name>: no keyframes" for an empty list.
BuildResult buildFromPoints(io::Points points, std::optional<std::vector<io::Keyframe>> keyframes,
                            const BuildParams& params, const std::string& name,
                            const std::string& keyframes_name = "keyframes");

/// How write() treats the output directory.
struct WriteOptions {
  bool make_parents = false;  ///< create missing parents of the directory (as mkdir -p); else refuse
  /// How report.json's warnings name parameters: the front end's names (the command line's
  /// "--min-pts"); by default the library's ("min_pts").
  ParameterSpelling spelling = fieldSpelling;
};

/// True when the build reads one finished octree (.bt/.ot) rather than points: frame, filters,
/// octree parameters and trajectory then do not apply.
bool readsOctree(const BuildParams& params);

/// The frame the outputs of `result` are in, as written into report.json and obstacles.json.
std::string outputFrame(const BuildResult& result);

/// Whether report.input_to_output is the whole change from input to output: false when the
/// alignment's drift model moved each point by its own part of the path.
bool inputToOutputExact(const BuildReport& report);

/// Writes map.bt (+ map.ot with params.write_ot), voxels.csv, obstacles.json, obstacles.obj,
/// report.json (+ trajectory.txt, the keyframes in the output frame, when the build had keyframes:
/// writeTumTrajectory) into `dir` whole or not at all: everything goes to a sibling staging directory
/// `.NAME.new<pid>` (locked while written) which then replaces `dir` in one atomic step (rename, or
/// renameat2 RENAME_EXCHANGE when `dir` exists); a failed run leaves the previous `dir` as it was.
/// Staging directories of killed runs are removed. `dir` may only be absent, empty or a previous
/// output (checkOutputDir); write() puts the marker kOutputMarker in it. Throws
/// hullmap::Error naming `dir`.
void write(const BuildResult& result, const std::filesystem::path& dir, const WriteOptions& options = {});

/// What write() may replace (checkOutputDir of output_dir.hpp, which write() calls twice: before it
/// writes and just before it swaps the directory in): never a directory holding an input or the
/// trajectory of `params`; missing parents made with options.make_parents. Call
/// `checkOutputDir(dir, outputPolicy(params, options))` before a long build, so that it does not fail
/// at its end.
OutputDirPolicy outputPolicy(const BuildParams& params, const WriteOptions& options = {});

/// The obstacles of an obstacles.json written by write() (or writeObstaclesJson), each with its id.
/// Throws hullmap::Error "<path>: <what>" on a missing file, another format or any malformed field.
std::vector<hulls::Obstacle> readObstacles(const std::filesystem::path& obstacles_json);

/// Reads and unions point files (any format the mapper reads); throws hullmap::Error naming them
/// when none holds a point.
io::PointSet readInputPoints(const std::vector<std::string>& inputs);

}  // namespace hullmap::pipeline
