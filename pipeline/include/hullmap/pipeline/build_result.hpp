#pragma once

// What a build did: BuildResult (the map, its voxels and labels, the obstacles, the surfaces) and its BuildReport.

#include <cstdint>
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
#include "hullmap/mapper/occupancy_map.hpp"
#include "hullmap/pipeline/build_params.hpp"

namespace hullmap::pipeline {

/// Label written into voxels.csv (BuildResult::clusters.labels) for voxels of the floor and of the
/// ceiling: they stay in the map but are not clustered (clustering::kNoise is -1).
inline constexpr std::int32_t kFloorLabel = -2;
inline constexpr std::int32_t kCeilingLabel = -3;
/// Label of the voxels set aside as the ground (a height field: BuildReport::ground).
inline constexpr std::int32_t kGroundLabel = -4;
/// The least share of the occupied voxels a fitted ground must take to explain the map's ground.
inline constexpr double kGroundMinShare = 0.2;

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

}  // namespace hullmap::pipeline
