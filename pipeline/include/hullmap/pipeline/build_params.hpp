#pragma once

// What a build is asked: BuildParams, one struct of each stage's settings (defaults are `hullmap build`'s).

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/auto_params.hpp"
#include "hullmap/clustering/cluster_extension.hpp"
#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/hulls/convex_parts.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/mapper/align.hpp"
#include "hullmap/mapper/floor.hpp"
#include "hullmap/mapper/frame.hpp"
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/mapper/terrain.hpp"

namespace hullmap::pipeline {

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

}  // namespace hullmap::pipeline
