#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/Marker.h>
#include <visualization_msgs/MarkerArray.h>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/hulls/obstacles.hpp"
#include "hullmap/io/point_cloud.hpp"
#include "hullmap/live/map_messages.hpp"
#include "hullmap/live/outputs.hpp"
#include "hullmap/mapper/occupancy_map.hpp"

/// Conversions between ROS1 messages and hullmap's types, for hullmap_node and the bag reader: each
/// copies a message's fields into hullmap::live's neutral types (or back) and calls live, which holds
/// the rules both ROS nodes share. No node handle, no publisher: plain functions on messages,
/// testable without a ROS master.
/// Coordinates are taken and given as they are (the input frame in, hullmap's z-up map frame out);
/// every function is reentrant.
namespace hullmap::ros1 {

/// ORB-SLAM (v1)'s map as its MapPublisher sends it on /ORB_SLAM/Map: live::OrbSlamMapMarkers
/// (the rule, shared with the ROS 2 node) over ROS1 Markers. Not thread-safe.
class OrbSlamMapMarkers {
 public:
  /// Takes one marker; true when the map changed. Throws hullmap::Error naming the marker
  /// ("MapPoints id 0: point 12 is not finite") when a map-points marker holds a NaN or infinite
  /// coordinate; the map is then left as it was.
  bool add(const visualization_msgs::Marker& marker);
  /// The map: the id 0 points, then the id 6 points (input frame).
  io::Points points() const { return markers_.points(); }
  /// True before any map-points marker (or after a DELETEALL).
  bool empty() const { return markers_.empty(); }
  void clear() { markers_.clear(); }

 private:
  live::OrbSlamMapMarkers markers_;
};

/// The x, y and z fields of every point of a cloud (FLOAT32 or FLOAT64 fields, little-endian),
/// in point order. Points with a NaN or infinite coordinate (the holes of an organised cloud) are
/// skipped and counted in `*non_finite` when given. Throws hullmap::Error when a field is missing
/// ("PointCloud2: no field z"), of another type, or the data is shorter than its header says.
io::Points cloudPoints(const sensor_msgs::PointCloud2& cloud, std::size_t* non_finite = nullptr);

/// The obstacles as RViz markers, frame and stamp from `header`: ns "hulls" one TRIANGLE_LIST per
/// obstacle (id = obstacle id, outward triangles; an obstacle in convex parts holds the triangles of
/// its parts' hulls, what path checks test, not the whole cluster's hull), ns "footprints" a closed
/// LINE_STRIP of the footprint at its z_min (with parts: a LINE_LIST of every part's polygon edges),
/// ns "labels" a TEXT_VIEW_FACING "id" above the hull. Ids in
/// `previous_ids` that are no longer obstacles get a DELETE in each namespace (stale markers go away
/// when the obstacle set shrinks).
visualization_msgs::MarkerArray obstacleMarkers(const std::vector<hulls::Obstacle>& obstacles,
                                                const std::vector<int>& previous_ids, const std_msgs::Header& header);

/// Occupied voxels as octomap_server's ~occupied_cells_vis_array: one CUBE_LIST per tree depth
/// 0..16 (ns = frame id, id = depth), the leaves (edge `resolution`, map units) in the depth-16
/// marker and DELETE for the empty depths, so RViz configs made for octomap_server show them.
visualization_msgs::MarkerArray occupiedCellMarkers(const std::vector<mapper::OccupiedVoxel>& voxels, double resolution,
                                                    const std_msgs::Header& header);

/// The footprints (of the convex parts, for an obstacle in parts) whose z range meets [min_z, max_z]
/// (map frame) rasterised into
/// an OccupancyGrid of `resolution` cells: 100 in every cell that the footprint polygon touches,
/// 0 elsewhere (free as far as the hulls know), over the footprints' bounding box plus `margin`
/// (map units) on each side. An empty map gives a 1x1 grid at the origin.
nav_msgs::OccupancyGrid projectedMap(const std::vector<hulls::Obstacle>& obstacles, double resolution, double min_z,
                                     double max_z, double margin, const std_msgs::Header& header);

/// A path check as RViz markers: ns "path_check" id 0, a LINE_LIST of the path's segments, red for
/// those that collide and green for the clear ones (width `line_width`, map units).
visualization_msgs::MarkerArray pathCheckMarkers(const std::vector<Eigen::Vector3d>& waypoints,
                                                 const collision::PathCheck& check, double line_width,
                                                 const std_msgs::Header& header);

/// A neutral marker as a ROS1 Marker with `header`.
visualization_msgs::Marker toMarker(const live::MarkerSpec& spec, const std_msgs::Header& header);

/// Neutral markers as a MarkerArray with `header`.
visualization_msgs::MarkerArray toMarkerArray(const std::vector<live::MarkerSpec>& specs,
                                              const std_msgs::Header& header);

/// A neutral grid as an OccupancyGrid with `header` (map_load_time: the header's stamp).
nav_msgs::OccupancyGrid toOccupancyGrid(const live::ProjectedGrid& grid, const std_msgs::Header& header);

/// A marker's key for live::OrbSlamMapMarkers (a view of its namespace).
live::MarkerKey markerKey(const visualization_msgs::Marker& marker);

/// A cloud's layout for live::cloudPoints (views of its field names).
live::CloudLayout cloudLayout(const sensor_msgs::PointCloud2& cloud);

}  // namespace hullmap::ros1
