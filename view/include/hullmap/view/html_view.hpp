#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/sim/ground_truth.hpp"

/// `hullmap view` as a library: a build directory (and paths, a roadmap, ground truth) drawn in 3D as
/// one self-contained HTML page that opens from file:// with no network and no server. The page runs
/// three.js (r111) from Debian's libjs-three, read when the page is written and inlined; the data
/// goes in as base64 typed arrays. Everything in the build's output frame (z up), map units.
/// Functions are reentrant; nothing is shared between calls.
namespace hullmap::view {

/// Where Debian's libjs-three installs three.js and its examples, and the package's name.
inline constexpr const char* kThreeDir = "/usr/share/javascript/three";
inline constexpr const char* kThreePackage = "libjs-three";

/// Most voxel cubes a page holds at its finest level by default; more are merged into coarser
/// cells (mergeVoxelCells). Measured: docs/DESIGN_NOTES.md, "html_view.hpp: kDefaultMaxInstances".
inline constexpr std::size_t kDefaultMaxInstances = 1000000;

/// Most cubes of a page's coarsest level (voxelLevels: each level's cells twice the last's); it draws the
/// finest level it can at about 0.1 s a frame (docs/DESIGN_NOTES.md, "html_view.hpp: kCoarsestCubes").
inline constexpr std::size_t kCoarsestCubes = 10000;

/// A path to check and draw, map frame, map units.
struct ViewPath {
  std::string name;                        ///< shown in the legend (e.g. the file name)
  std::vector<Eigen::Vector3d> waypoints;  ///< at least two
};

/// A roadmap's drawable part (planning::Roadmap's nodes and edges; view does not depend on the
/// planning library): ground plane, drawn at height `z`.
struct ViewRoadmap {
  std::string name;
  std::vector<Eigen::Vector2d> nodes;
  std::vector<std::vector<Eigen::Vector2d>> edges;  ///< each edge's polyline
  std::vector<double> clearance;                    ///< per edge, map units
  double z = 0.0;                                   ///< map frame
};

/// What a page shows besides the build directory.
struct ViewInputs {
  std::vector<ViewPath> paths;  ///< checked against the build's hulls at `radius`
  double radius = 0.0;          ///< drone radius for `paths`, map units (>= 0)
  std::optional<ViewRoadmap> roadmap;
  std::optional<sim::GroundTruth> truth;  ///< drawn as wireframes
  std::string truth_name;                 ///< shown in the legend
};

/// A path with its check: pipeline::pathChecker(...).checkPath(waypoints, radius), the call
/// `hullmap check --path` makes.
struct CheckedPath {
  ViewPath path;
  collision::PathCheck check;
};

/// Everything a page draws, in memory: what readScene() reads from a build directory, or a
/// program's own.
struct ViewScene {
  std::string title;  ///< the page's title (the build directory's name)
  /// The build's report.json (frame, parameters, counts, floor and ceiling): shown in the legend.
  nlohmann::json report = nlohmann::json::object();
  double resolution = 0.05;                ///< voxel edge, map units (> 0)
  std::vector<Eigen::Vector3d> centers;    ///< occupied voxel centres (voxels.csv)
  std::vector<std::int32_t> labels;        ///< per voxel: obstacle id, -1 noise, -2 floor, -3 ceiling
  std::vector<hulls::Obstacle> obstacles;  ///< with their convex parts (obstacles.json)
  std::vector<io::Keyframe> keyframes;     ///< trajectory.txt; empty when the build had none
  std::vector<CheckedPath> paths;
  double radius = 0.0;  ///< the paths' drone radius
  std::optional<ViewRoadmap> roadmap;
  std::optional<sim::GroundTruth> truth;
  std::string truth_name;
};

/// Reads a build directory (voxels.csv, obstacles.json, report.json and trajectory.txt when present)
/// and checks `inputs.paths` against its hulls with pipeline::pathChecker, as `hullmap check` does.
/// Throws hullmap::Error naming the file (and line) at fault, or "radius" (negative or not finite),
/// or "paths" (a path with fewer than two waypoints).
ViewScene readScene(const std::filesystem::path& build_dir, ViewInputs inputs);

/// How a page is written.
struct ViewParams {
  std::filesystem::path three_dir = kThreeDir;       ///< holds three.min.js and examples/js/controls/OrbitControls.js
  std::size_t max_instances = kDefaultMaxInstances;  ///< voxel cubes held at the finest level (>= 1)
};

/// Voxels merged for drawing: each cell of `cell` = `factor` x resolution (factor a power of two,
/// 1 when nothing is merged) holds one cube. The cells' lattice is the voxels' own, anchored at the
/// smallest voxel index on each axis, so a factor of 1 gives back every voxel's centre.
struct VoxelCells {
  int factor = 1;
  double cell = 0.0;                     ///< edge of a drawn cube, map units
  std::vector<Eigen::Vector3d> centers;  ///< one per cell, sorted by label, then by cell index (z, y, x)
  std::vector<std::int32_t> labels;      ///< per cell
  std::vector<std::size_t> voxels;       ///< per cell: voxels merged into it
};

/// Merges voxels into the coarsest cells needed to draw at most `max_cells` of them: the smallest
/// power-of-two factor whose cells number at most `max_cells` (factor 1: no merge). A cell takes the
/// label of its voxels by priority: an obstacle id (the most voxels; ties to the smaller id) before
/// noise (-1), noise before floor (-2), floor before ceiling (-3), so no obstacle disappears into a
/// noise or floor cell. Voxels are placed on the lattice of `resolution` by rounding their centres.
/// Throws hullmap::Error naming "max_instances" (0), "resolution" (not > 0), or when the centres span
/// more than 65,536 voxels on an axis (more than an octree holds) or labels and centres differ in size.
VoxelCells mergeVoxelCells(const std::vector<Eigen::Vector3d>& centers, const std::vector<std::int32_t>& labels,
                           double resolution, std::size_t max_cells);

/// The levels of detail a page holds: the first is mergeVoxelCells(centers, labels, resolution,
/// max_cells); each next one merges cells of twice the factor (the same rule, from the voxels), until
/// one holds at most `coarsest_cells` cells (or the factor reaches 65,536). Throws as mergeVoxelCells.
std::vector<VoxelCells> voxelLevels(const std::vector<Eigen::Vector3d>& centers,
                                    const std::vector<std::int32_t>& labels, double resolution, std::size_t max_cells,
                                    std::size_t coarsest_cells = kCoarsestCubes);

/// What a page holds, for the command's summary and for tests.
struct ViewPage {
  std::string html;                 ///< the document
  std::size_t voxels = 0;           ///< occupied voxels of the scene
  std::size_t instances = 0;        ///< cubes at the finest level (cells after merging)
  int merge_factor = 1;             ///< VoxelCells::factor of the finest level
  std::vector<std::size_t> levels;  ///< cubes at each level of detail, finest first
  std::size_t hulls = 0;            ///< convex parts drawn (whole hulls for obstacles without parts)
  std::size_t colliding_paths = 0;  ///< paths whose check found a collision
};

/// The page of a scene. Reads three.js from params.three_dir; throws hullmap::Error naming
/// "three_dir" (and the package libjs-three) when it is missing, or as mergeVoxelCells.
ViewPage renderPage(const ViewScene& scene, const ViewParams& params = {});

/// renderPage written to `html` atomically (a temporary file renamed; nothing is left on failure).
/// Throws hullmap::Error naming `html` when it cannot be written, or as renderPage.
ViewPage writePage(const ViewScene& scene, const std::filesystem::path& html, const ViewParams& params = {});

}  // namespace hullmap::view
