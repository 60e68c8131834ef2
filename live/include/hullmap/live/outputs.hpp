#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/live/map_messages.hpp"
#include "hullmap/mapper/occupancy_map.hpp"

/// What the nodes publish, as neutral structs that each front end copies into its own messages
/// (with its header: frame id and stamp). Everything is in hullmap's z-up map frame, map units.
/// Functions are reentrant.
namespace hullmap::live {

struct Rgba {
  float r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f;
};

/// One visualization_msgs/Marker without its header: pose orientation is always the identity.
struct MarkerSpec {
  std::string ns;
  int id = 0;
  int type = 0;  ///< marker::k* (0 for a deletion)
  int action = marker::kAdd;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d scale = Eigen::Vector3d::Zero();
  Rgba color;
  std::vector<Eigen::Vector3d> points;
  std::vector<Rgba> colors;  ///< per point (path checks), else empty
  std::string text;
};

/// The obstacles as RViz markers: ns "hulls" one TRIANGLE_LIST per obstacle (id = obstacle id,
/// outward triangles; an obstacle in convex parts holds the triangles of its parts' hulls, what
/// path checks test, not the whole cluster's hull), ns "footprints" a closed LINE_STRIP of the
/// footprint at its z_min (with parts: a LINE_LIST of every part's polygon edges), ns "labels" a
/// TEXT_VIEW_FACING "id" above the hull. Ids in `previous_ids` that are no longer obstacles get a
/// DELETE in each namespace (stale markers go away when the obstacle set shrinks).
std::vector<MarkerSpec> obstacleMarkers(const std::vector<hulls::Obstacle>& obstacles,
                                        const std::vector<int>& previous_ids);

/// Occupied voxels as octomap_server's occupied_cells_vis_array: one CUBE_LIST per tree depth
/// 0..16 (ns = `ns`, the frame id there; id = depth), the leaves (edge `resolution`, map units) in
/// the depth-16 marker and DELETE for the empty depths, so RViz configs made for octomap_server show
/// them.
std::vector<MarkerSpec> occupiedCellMarkers(const std::vector<mapper::OccupiedVoxel>& voxels, double resolution,
                                            const std::string& ns);

/// A path check as RViz markers: ns "path_check" id 0, a LINE_LIST of the path's segments, red for
/// those that collide and green for the clear ones (width `line_width`, map units); a DELETE when
/// the path has no segment.
std::vector<MarkerSpec> pathCheckMarkers(const std::vector<Eigen::Vector3d>& waypoints,
                                         const collision::PathCheck& check, double line_width);

/// nav_msgs/OccupancyGrid's contents: row-major cells from `origin` (the corner of cell 0, z = 0),
/// 100 occupied, 0 free.
struct ProjectedGrid {
  double resolution = 0.0;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  std::vector<std::int8_t> data;
};

/// The most cells projectedGrid() draws (64 MB of int8, what one ROS message can still carry).
inline constexpr std::size_t kMaxGridCells = std::size_t{1} << 26;

/// The footprints (of the convex parts, for an obstacle in parts) whose z range meets [min_z, max_z]
/// rasterised into a grid of `resolution` cells: 100 in every cell that the footprint polygon
/// touches, 0 elsewhere (free as far as the hulls know), over the footprints' bounding box plus
/// `margin` (map units) on each side, the origin on multiples of the resolution. An empty map gives
/// a 1x1 grid at the origin. Throws hullmap::Error naming `resolution` unless it is finite and > 0, or
/// when the grid would exceed kMaxGridCells.
ProjectedGrid projectedGrid(const std::vector<hulls::Obstacle>& obstacles, double resolution, double min_z,
                            double max_z, double margin);

}  // namespace hullmap::live
