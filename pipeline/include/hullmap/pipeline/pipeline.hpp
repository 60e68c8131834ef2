#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/auto_params.hpp"
#include "hullmap/clustering/cluster_extension.hpp"
#include "hullmap/clustering/coplanar_merge.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/clustering/outlier_trim.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/warning.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/align.hpp"
#include "hullmap/mapper/floor.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/mapper/terrain.hpp"
#include "hullmap/pipeline/output_dir.hpp"

/// The whole build of `hullmap build` as a library: point files (or points in memory, or one .bt/.ot)
/// -> map frame (a reference trajectory's, or an up axis and scale) -> floor found and levelled ->
/// filters -> OctoMap octree -> floor/ceiling voxels set aside -> eps/minPts chosen from the map ->
/// exact DBSCAN of the obstacle voxels -> convex obstacles split into convex parts, and the output
/// directory it writes. Everything in the z-up map frame, map units (metres for a
/// metric SLAM map). Functions are reentrant: two builds may run at once on different params; each
/// build uses all cores (TBB) in the caller's arena.
namespace hullmap::pipeline {

/// Label written into voxels.csv (BuildResult::clusters.labels) for voxels of the floor and of the
/// ceiling: they stay in the map but are not clustered (clustering::kNoise is -1).
inline constexpr std::int32_t kFloorLabel = -2;
inline constexpr std::int32_t kCeilingLabel = -3;
/// Label of the voxels set aside as the ground (a height field: BuildReport::ground).
inline constexpr std::int32_t kGroundLabel = -4;
/// The least share of the occupied voxels a fitted ground must take to explain the map's ground.
inline constexpr double kGroundMinShare = 0.2;

/// Whether a floor found by the build levels the map: rotates the floor level and moves it to
/// z = 0 (the points, the keyframes, the origin and every output with them).
enum class Level {
  kAuto,  ///< only a camera's frame (levelsMap): ORB-SLAM's maps, and inputs whose up axis is not z
  kOn,    ///< always when a floor is found (needs floor kAuto; not with align: the reference sets the frame)
  kOff,   ///< never: the map stays in the frame it came in
};

/// `--align REF`: a metric reference trajectory of the keyframes (see mapper::alignTrajectory).
struct AlignSettings {
  std::filesystem::path reference;  ///< TUM or GPS file
  io::ReferenceFormat format = io::ReferenceFormat::kTum;
  mapper::AlignParams params;  ///< timestamp tolerance, seconds
  /// The reference poses already in memory, as io::parseReferenceTrajectory gives them (metres,
  /// z up; GPS fixes converted): used instead of reading `reference`, which then only names them
  /// (report.json's "align"). A front end that takes an array sets it.
  std::optional<std::vector<io::ReferencePose>> poses = std::nullopt;
};

/// Everything a build can be asked, typed. Defaults are `hullmap build`'s.
struct BuildParams {
  /// Map-point files (ORB-SLAM echo dump, text/CSV, XYZ, PCD, PLY; formats detected), unioned in
  /// order; or exactly one .bt/.ot, a finished map (then frame, filters, octree and trajectory do
  /// not apply and every voxel weighs 1). Ignored by buildFromPoints.
  std::vector<std::filesystem::path> inputs;
  /// TUM keyframe trajectory (input frame): free space is ray-cast from the keyframes.
  std::optional<std::filesystem::path> trajectory;
  /// Sensor origin, input frame: the points are inserted as one scan from there (free space along
  /// the rays). Not with `trajectory`.
  std::optional<Eigen::Vector3d> origin;
  /// Similarity from the keyframes to a metric reference trajectory (needs `trajectory`): points
  /// and keyframes are moved into the reference's frame (metres, z up), and `frame` does not apply.
  std::optional<AlignSettings> align;
  mapper::FrameParams frame;  ///< input -> z-up map frame (up axis, scale); not with `align`
  /// The floor: kAuto (default) searches it (mapper::findBoundingPlane on the points, band = the
  /// resolution; with `align` only its height, the reference defining up). Found, it is levelled to
  /// z = 0 (rotation and shift) when `level` says so; else the map keeps its frame and the plane is
  /// used as found (tilted or not). kHeight: the plane z = height (map frame, after align/frame).
  /// Voxels within 1.25 voxels of it (or under it) are not clustered; it is an obstacle for path
  /// checks (BuildResult::surfaces).
  mapper::PlaneSetting floor;
  /// Whether a found floor levels the map; kAuto: only a camera's frame (levelsMap).
  Level level = Level::kAuto;
  /// The ground when no floor plane explains it (floor kAuto, a map not levelled, point inputs; no
  /// plane found, or the plane found strays from the terrain's measured heights: outdoors, slopes,
  /// monocular scale drift; PlaneReport::ground_instead): mapper::fitTerrain with these settings on the
  /// build's sample of its points (at most 2^18, every k-th) under the keyframes, then raised into
  /// the middle of its points. When at least kGroundMinShare of the points lie on it, its height
  /// field is an obstacle for path checks (BuildResult::surfaces, "ground") and the occupied voxels
  /// whose centre lies less than half a voxel plus half of terrain.initial_threshold above it (or
  /// under it) are set aside: kGroundLabel, not clustered, still in map.bt. Map units: the defaults
  /// are metres (2 m cells), for a metric map.
  mapper::TerrainParams terrain;
  bool ground = true;  ///< false: never fit the ground
  /// For level kAuto: whether the points are in a camera's frame (a monocular SLAM map is in its
  /// first camera's). nullopt: judged from the inputs (levelsMap). A live node sets it from the
  /// topic (ORB-SLAM's map markers: true; a PointCloud2: false).
  std::optional<bool> camera_frame;
  /// The ceiling, likewise (never moves the map); default kNone.
  mapper::PlaneSetting ceiling{mapper::PlaneSetting::Mode::kNone, 0.0};
  /// Crop box and z bounds, in the output frame: after up/scale or align, and after levelling (the
  /// input frame itself when none of them moved the map).
  mapper::FilterParams filters;
  mapper::OctreeParams octree;  ///< resolution 0.05, octomap's sensor model, unbounded rays
  /// true (default): when the map's points lie farther apart than the auto rule can reach at
  /// octree.resolution (the typical point's 4th nearest, three points in four, beyond
  /// auto_rule.max_eps_voxels voxels: most voxels would be noise; warning 10's measure, on the
  /// points after align/frame), the octree is built at that spacing / 2.5 rounded to 1, 2 or 5 x
  /// 10^n instead (clustering::resolutionForSpacing; BuildReport::resolution, and
  /// BuildResult::params holds the one used). Maps dense enough for it keep octree.resolution. false:
  /// octree.resolution as given (the CLI when --resolution is given; the live nodes). An `eps` given
  /// also keeps octree.resolution (the two are chosen together).
  bool adapt_resolution = true;
  /// DBSCAN radius, map units; nullopt (default): chosen from the map (clustering::chooseDbscanParams
  /// with `auto_rule`). A given value wins.
  std::optional<double> eps;
  /// DBSCAN core threshold, in map points (voxels weigh their points); nullopt (default): auto.
  std::optional<int> min_pts;
  clustering::Metric metric = clustering::Metric::kXyz;  ///< DBSCAN distance (xy: top view)
  clustering::AutoParamsRule auto_rule;                  ///< the rule behind auto eps / minPts
  /// After DBSCAN, grow its clusters through the noise voxels that are dense at a lower level
  /// (clustering::extendClusters with clustering::extensionParams(the DBSCAN parameters used,
  /// `extension_rule`)): sparse structure attached to a cluster (thin legs, edges) joins it; no
  /// cluster is created or merged. nullopt (default): on when `min_pts` is auto (the auto minPts
  /// keeps outliers out and the extension brings back the sparse structure it leaves out), off when
  /// `min_pts` is given (the clusters are then exactly DBSCAN's). true / false: always / never.
  std::optional<bool> extension;
  clustering::ClusterExtensionRule extension_rule;  ///< the rule behind the extension
  /// Convex parts of each cluster (hulls::addConvexParts) with concavity bound
  /// `convex_parts->concavity` (0: hulls::defaultConcavity, 3 voxels); nullopt: one hull per
  /// cluster. The keyframes (with `trajectory`) are kept out of every part's hull.
  /// `convex_parts->flat_gap` (G of flat parts) unset: the DBSCAN eps used; 0: off (G = T).
  std::optional<hulls::ConvexPartsParams> convex_parts = hulls::ConvexPartsParams{};
  /// With the extension and convex parts: a part of at most this many voxels, at most one of them core, of
  /// an obstacle with other parts, and farther than 2 T (the concavity) from the floor's, ceiling's
  /// and ground's voxels, is dropped, its voxels made noise (hulls::StrayParts: the stray map points
  /// a wide eps took in off a surface). 0: keep every part.
  std::size_t stray_part_voxels = 3;
  /// With convex parts: each sparse part grows in its own plane by a share of its point spacing
  /// (hulls::SparseEdges at its defaults): the hulls reach the edges and corners a sparse map's last
  /// points stop short of. Off: every part is the hull of its voxels.
  bool sparse_edges = true;
  /// Point files only (no trajectory, no origin): they stream batch by batch into the octree, so a
  /// map larger than memory builds. When the floor may have to be levelled (floor auto, no align),
  /// inputs totalling less than this many bytes are read whole instead (one pass: the levelling is
  /// known before the octree is built; 256 MiB of text is about 8M points), larger ones stream twice
  /// (the first pass finds the floor). 0: always stream. The outputs are the same either way.
  std::uintmax_t stream_above_bytes = std::uintmax_t(256) << 20;
  bool write_ot = false;  ///< write() also writes map.ot (full probabilities)
};

/// How the octree's resolution was chosen (BuildParams::adapt_resolution).
struct ResolutionReport {
  double given = 0.0;             ///< BuildParams::octree.resolution
  std::optional<double> spacing;  ///< the points' spacing measured (none: too few points)
  double used = 0.0;              ///< the octree's: given, or coarser for a sparse map
};

/// What the ground stage found (BuildParams::terrain): the height field's grid and how much of it
/// was measured.
struct GroundReport {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< lower corner of the grid, map frame
  double step = 0.0;                                 ///< cell side, map units
  std::size_t nx = 0, ny = 0;                        ///< nodes along x and y
  std::size_t cells_with_points = 0;                 ///< cells holding a voxel
  std::size_t measured_cells = 0;                    ///< cells whose height was measured as ground; others interpolated
  std::size_t filled_cells = 0;                      ///< cells interpolated from the measured ones
  double fill_above_support_max = 0.0;  ///< most a filled node stands over its support (mapper::slopeSupport)
  double coverage = 0.0;                ///< measured_cells / (nx * ny)
  double lowest = 0.0, highest = 0.0;   ///< the surface's lowest and highest node, map frame
  double raised_most = 0.0;             ///< most a node was raised to hold the ground voxels, map units
  std::size_t lowered = 0;              ///< nodes then held under a keyframe
  std::size_t voxels = 0;               ///< occupied voxels set aside as ground
};

/// What the floor or ceiling stage found.
struct PlaneReport {
  mapper::PlaneSetting setting;
  std::optional<mapper::Plane> plane;  ///< the plane used (map frame after levelling); nullopt: none
  mapper::PlaneFit fit;                ///< the search's result (kAuto only)
  bool levelled = false;               ///< the map was rotated/shifted to put this floor at z = 0
  /// The floor found does not explain the ground (its measured heights stray from the plane): the
  /// ground's height field stands for it (BuildReport::ground); `plane` is then empty.
  bool ground_instead = false;
  std::size_t voxels = 0;  ///< occupied voxels set aside as this surface
};

/// The DBSCAN parameters a build used and where they came from.
struct ClusterParamsReport {
  clustering::DbscanParams used;  ///< eps, min_pts, metric
  bool eps_auto = false;
  bool min_pts_auto = false;
  std::optional<clustering::AutoParams> chosen;  ///< what the auto rule measured (when either is auto)
  /// With BuildParams::extension: the parameters of the extension pass and what it did.
  std::optional<clustering::ClusterExtensionParams> extension_params;
  clustering::ClusterExtension extension;
  /// With the extension: the outlier trim after it (clustering::trimOutliers, radius 3 voxels, reach
  /// the extension's, at least the radius) and what it did.
  std::optional<clustering::OutlierTrimParams> trim_params;
  clustering::OutlierTrim trim;
  /// With the extension: the coplanar merge after it (clustering::mergeCoplanarClusters, reach the
  /// eps used, thickness 3 voxels) and what it did.
  std::optional<clustering::CoplanarMergeParams> coplanar_params;
  clustering::CoplanarMerge coplanar;
};

/// Account of what happened to the input points, stage by stage.
struct PointAccount {
  std::size_t read = 0;
  std::map<std::string, std::size_t> dropped;  ///< reason ("out_of_octree", "outside_crop", ...) -> count
  std::size_t used = 0;
};

/// What a build did, as data; reportJson() makes report.json of it.
struct BuildReport {
  std::vector<io::InputStats> inputs;  ///< per input file, in order
  PointAccount points;
  std::size_t keyframes = 0;                   ///< keyframes read (0 without a trajectory)
  std::optional<mapper::Alignment> alignment;  ///< with params.align
  /// With params.align in GPS: reference lines dropped for having no fix, by reason ("no_fix":
  /// latitude = longitude = 0; "non_finite"; "out_of_range"): see io::ReferenceStats.
  std::map<std::string, std::size_t> reference_dropped;
  /// Map frame (after align/frame, before levelling) -> output frame: the floor's levelling.
  Eigen::Isometry3d levelling = Eigen::Isometry3d::Identity();
  /// Input coordinates -> output coordinates: the product of the up axis and scale (or the
  /// alignment) and the levelling; identity for an octree read as it is. `check` and `plan` take
  /// input-frame coordinates through it (mapper::inverse for the way back).
  /// With the alignment's drift model (alignment->drift) it is the whole path's similarity only:
  /// each point moved by its own part of the path (inputToOutputExact is false).
  mapper::Similarity input_to_output;
  PlaneReport floor;
  PlaneReport ceiling;
  std::optional<GroundReport> ground;          ///< when a ground was found (BuildParams::terrain)
  std::optional<ResolutionReport> resolution;  ///< with BuildParams::adapt_resolution
  ClusterParamsReport cluster_params;
  std::optional<hulls::ConvexPartsSummary> parts;  ///< with params.convex_parts
  std::size_t keyframes_inside_hulls = 0;          ///< keyframes inside some part's hull (whole hull without parts)
  std::size_t camera_voxels = 0;                   ///< occupied voxels holding a keyframe: in no obstacle
  std::vector<std::pair<std::string, double>> timings_ms;   ///< stage -> wall time, ms, in order
  std::vector<std::pair<std::string, double>> peak_rss_mb;  ///< stage -> process peak RSS at its end, MB
  /// What the outputs leave out or misstate (most voxels noise, no obstacle, eps below the
  /// resolution, a tilted floor), as codes with numbers: report.json records them in the words of
  /// WriteOptions::spelling, `hullmap build` prints them in its own.
  std::vector<Warning> warnings;
};

/// The occupied voxels of a map clustered and wrapped: the one voxel -> DBSCAN -> obstacles step.
struct ClusteredVoxels {
  std::vector<mapper::OccupiedVoxel> voxels;  ///< sorted by octree key (OccupancyMap::occupiedVoxels)
  clustering::DbscanResult clusters;          ///< per voxel: label, core; cluster sizes in voxels
  std::vector<hulls::Obstacle> obstacles;     ///< one per cluster, id = cluster label
};

/// The in-memory result of a build: what write() puts in the output directory.
struct BuildResult {
  BuildParams params;  ///< as given (inputs included)
  mapper::OccupancyMap map{mapper::OctreeParams{}};
  std::vector<mapper::OccupiedVoxel> voxels;  ///< see ClusteredVoxels
  /// Voxel labels: clusters.labels[i] is voxels[i]'s (kFloorLabel / kCeilingLabel / kGroundLabel
  /// for the floor's, ceiling's and ground's voxels, which are counted in neither noise nor clusters).
  clustering::DbscanResult clusters;
  std::vector<hulls::Obstacle> obstacles;  ///< what collision::HullChecker takes (with parts)
  /// The floor and ceiling found or given, as solid half-spaces for path checks (HullChecker's
  /// surfaces): the solid reaches up to the plane, or to the top of its highest voxel when that is
  /// higher (every voxel set aside as floor lies inside it completely, as a cluster's voxels lie
  /// inside its hull). Named "floor" and "ceiling". The ground (BuildReport::ground) as a height
  /// field, named "ground", every voxel set aside as ground under it.
  std::vector<collision::Surface> surfaces;
  std::vector<io::Keyframe> keyframes;  ///< output frame (with params.trajectory)
  BuildReport report;
};

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

namespace detail {
/// Test-only: when set, build() and write() call it at the start of each stage with the stage's
/// name: "read", "frame_and_filters", "octree", "dbscan", "obstacles", then write()'s "write" (staging
/// directory made and locked), "wrote_map", "wrote_voxels", "wrote_obstacles" (called one after the
/// other once map.bt, voxels.csv and the obstacle files, written side by side, are all written) and
/// "move_into_place" (every file written, the directory not yet in place); a test stops the run there (throw, or kill
/// the process) to see what a run interrupted at that stage leaves behind. Not thread-safe; nullptr (the default) does
/// nothing.
extern void (*stage_hook)(const char* stage);

/// The build's rims step, exposed for its tests. After DBSCAN, each floor voxel (kFloorLabel) joins
/// a cluster (labels >= 0 on entry) it stands under, by the first of two rules that finds one;
/// "above" is "at its layer or above", and for a ceiling voxel (kCeilingLabel) "below" likewise;
/// `layers` = max(2, `reach` / `resolution`) (floor, + 1e-9):
///  1. the nearest clustered voxel (squared lattice distance, ties to the lower label) in its
///     column neighbourhood (|di|, |dj| <= 1 cell) at most `layers` above;
///  2. else the nearest such voxel up to 2 * `layers` above that is the lower end of a face of its
///     cluster: two voxels of its cluster within `reach` of it (centre distance) lie at least 2
///     layers higher (a wall, a box's side or a table leg goes on up; a table top, flat, does not,
///     so the floor under a top more than `layers` up stays floor).
/// The foot of a wall or box lies in the floor's band, and on a sparse map the voxels above a foot
/// voxel are often empty for more than `reach`. (A third rule, joining floor voxels within 1.5 cells
/// of the line between two low voxels of a cluster, was tried and left out: it laid a ledge of floor
/// voxels along the walls' feet that came out as parts of their own.) `centers` are voxel centres on the lattice of
/// `resolution` (map frame, z up); `reach` (map units): build passes the DBSCAN eps used, at most the auto rule's upper
/// clamp (max_eps_voxels voxels: 0.4 m at 5 cm), so that a large eps given by hand does not join most of the floor.
/// Voxels join clusters as they were on entry (no chains). Throws hullmap::Error when the sizes differ.
void attachSurfaceRims(const std::vector<Eigen::Vector3d>& centers, double resolution, double reach,
                       std::vector<std::int32_t>& labels);
}  // namespace detail

}  // namespace hullmap::pipeline
