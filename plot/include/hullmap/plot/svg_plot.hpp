#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/clustering/dbscan.hpp"
#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/plot/colour.hpp"
#include "hullmap/plot/picture_output.hpp"

namespace hullmap::plot {

/// Which plane the picture shows. The map frame is z up.
enum class PlotView {
  kTop,   ///< x right, y up, seen from above
  kSide,  ///< x right, z up, seen from -y
};

/// A path and the answer of collision::HullChecker::checkPath(waypoints, radius) for it.
struct PlotPath {
  std::string name;                        ///< named in the caption (e.g. the file); may be empty
  std::vector<Eigen::Vector3d> waypoints;  ///< map frame, map units
  double radius = 0.0;                     ///< drone radius, map units
  collision::PathCheck check;              ///< one SegmentCheck per consecutive pair of waypoints
};

/// A roadmap to draw under the paths (planning::Roadmap's drawable part; plot does not depend on
/// the planning library). Ground plane, map units.
struct PlotRoadmap {
  std::vector<Eigen::Vector2d> nodes;
  std::vector<std::vector<Eigen::Vector2d>> edges;  ///< each edge's polyline
  std::vector<double> clearance;                    ///< per edge, map units
};

/// Colour of the i-th path (one per drone): blue, orange, green, purple, red, teal, pink, olive,
/// then again. Pure function.
Rgb pathColour(std::size_t index);

/// Everything `hullmap plot` draws.
struct MapPlot {
  std::vector<Eigen::Vector3d> centers;  ///< occupied voxel centres, map frame, map units
  std::vector<std::int32_t> labels;      ///< per voxel: cluster label or clustering::kNoise
  double voxel_size = 0.05;              ///< leaf edge length, map units (> 0)
  std::vector<hulls::Obstacle> obstacles;
  std::optional<PlotRoadmap> roadmap;  ///< drawn in the top view only (it is a ground-plane graph)
  std::vector<PlotPath> paths;         ///< one colour each (pathColour), drawn over the roadmap
  /// Keyframe positions (map frame; a build's trajectory.txt), drawn as the camera's path; may be empty.
  std::vector<Eigen::Vector3d> keyframes;
  /// The floor's label (pipeline::kFloorLabel): its voxels drawn light brown under the rest (data-label
  /// -2), their cells outlined. nullopt: drawn as noise.
  std::optional<std::int32_t> floor_label;
  std::vector<std::string> caption;  ///< lines printed under the picture (parameters)
  PlotView view = PlotView::kTop;
};

/// What a rendering drew, for the command's summary and for tests.
struct SvgPicture {
  std::string svg;                ///< the document
  std::size_t cells = 0;          ///< projected cells drawn (voxels merged per cell)
  std::size_t hidden_voxels = 0;  ///< voxels outside the view (far outliers), not drawn
};

/// Renders a map as one SVG document (no external resources).
///
/// Voxels are projected on the view plane and merged: each cell of the plane (voxel_size square,
/// aligned to the octree grid) is drawn once, in the colour of one voxel above it: a clustered voxel
/// wins over noise; among equals the topmost (top view) or the nearest to the viewer, smallest y
/// (side view). Runs of equal cells in a row become one rectangle and all rectangles of a label one
/// <path class="cells" data-label="L">, so 100k voxels make a file of a few hundred kB at most.
/// The view spans the clustered voxels, the obstacles, the path and the bulk of the noise (5% to
/// 95% quantiles per axis), grown to take in every noise voxel within the view's extent of it;
/// noise voxels farther out (gross outliers, e.g. ORB-SLAM points kilometres away) are counted in
/// SvgPicture::hidden_voxels and in the caption, not drawn.
///
/// Each obstacle is outlined as <polygon class="footprint" id="obstacle-ID"> (top view: its footprint
/// polygon; side view: the x-z outline of its hull) and numbered with its id. A roadmap (top view)
/// is drawn as <g class="roadmap"> of <polyline class="roadmap-edge" data-clearance=".."> and
/// <circle class="roadmap-node">. Each path is a <g class="path" data-index="i"> in pathColour(i)
/// with a band of its radius; segments that collide are red lines of class "colliding-segment", the
/// first contact a red circle of class "first-contact". The keyframes are a dashed purple
/// <g class="trajectory"> (a polyline and a dot each); the floor's voxels, with floor_label, are
/// outlined by <polygon class="floor-outline"> (dashed), the convex hull of their cells in the view
/// plane. Axes are in map units with a scale bar.
/// Throws hullmap::Error on voxel_size <= 0 or a labels/centers size mismatch.
SvgPicture renderMapSvg(const MapPlot& plot);

/// One DBSCAN run of a sweep: its parameters and the label of every point.
struct SweepPanel {
  double eps = 0.0;
  int min_pts = 0;
  std::vector<std::int32_t> labels;  ///< per point, same order as the points
};

/// Small multiples, one top view per panel (the seed report's figures 3 and 4 in one picture).
/// When the panels form a full grid of distinct eps x distinct min_pts they are laid out with eps
/// across and min_pts down; otherwise in the given order, ceil(sqrt(n)) per row. All panels share
/// the same bounds and scale; far outliers are left out as in renderMapSvg and counted in the caption. Points are
/// merged into square cells of `cell_size` map units (<= 0: 1/150 of the larger extent) as renderMapSvg merges voxels:
/// clustered wins over noise, then the first point in input order. Each panel is a <g class="panel" data-eps=".."
/// data-min-pts=".."> titled with its parameters, cluster count and noise share. Throws hullmap::Error when a panel's
/// labels do not match the points.
std::string renderSweepSvg(const std::vector<Eigen::Vector3d>& points, const std::vector<SweepPanel>& panels,
                           double cell_size, const std::string& title);

}  // namespace hullmap::plot
