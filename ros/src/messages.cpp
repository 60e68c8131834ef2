#include "hullmap/ros1/messages.hpp"

namespace hullmap::ros1 {
namespace {

geometry_msgs::Point toPoint(const Eigen::Vector3d& v) {
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

std_msgs::ColorRGBA toColor(const live::Rgba& c) {
  std_msgs::ColorRGBA color;
  color.r = c.r;
  color.g = c.g;
  color.b = c.b;
  color.a = c.a;
  return color;
}

}  // namespace

live::MarkerKey markerKey(const visualization_msgs::Marker& m) { return {m.ns, m.id, m.type, m.action}; }

live::CloudLayout cloudLayout(const sensor_msgs::PointCloud2& cloud) {
  live::CloudLayout layout;
  for (const auto& f : cloud.fields) layout.fields.push_back({f.name, f.offset, f.datatype});
  layout.width = cloud.width;
  layout.height = cloud.height;
  layout.point_step = cloud.point_step;
  layout.row_step = cloud.row_step;
  layout.is_bigendian = cloud.is_bigendian;
  return layout;
}

bool OrbSlamMapMarkers::add(const visualization_msgs::Marker& m) { return markers_.add(markerKey(m), m.points); }

io::Points cloudPoints(const sensor_msgs::PointCloud2& cloud, std::size_t* non_finite) {
  return live::cloudPoints(cloudLayout(cloud), cloud.data.data(), cloud.data.size(), non_finite);
}

visualization_msgs::Marker toMarker(const live::MarkerSpec& spec, const std_msgs::Header& header) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = spec.ns;
  m.id = spec.id;
  m.type = spec.type;
  m.action = spec.action;
  m.pose.position = toPoint(spec.position);
  m.pose.orientation.w = 1.0;
  m.scale.x = spec.scale.x();
  m.scale.y = spec.scale.y();
  m.scale.z = spec.scale.z();
  m.color = toColor(spec.color);
  m.points.reserve(spec.points.size());
  for (const auto& p : spec.points) m.points.push_back(toPoint(p));
  for (const auto& c : spec.colors) m.colors.push_back(toColor(c));
  m.text = spec.text;
  return m;
}

visualization_msgs::MarkerArray toMarkerArray(const std::vector<live::MarkerSpec>& specs,
                                              const std_msgs::Header& header) {
  visualization_msgs::MarkerArray array;
  array.markers.reserve(specs.size());
  for (const auto& spec : specs) array.markers.push_back(toMarker(spec, header));
  return array;
}

nav_msgs::OccupancyGrid toOccupancyGrid(const live::ProjectedGrid& g, const std_msgs::Header& header) {
  nav_msgs::OccupancyGrid grid;
  grid.header = header;
  grid.info.map_load_time = header.stamp;
  grid.info.resolution = static_cast<float>(g.resolution);
  grid.info.width = g.width;
  grid.info.height = g.height;
  grid.info.origin.position.x = g.origin.x();
  grid.info.origin.position.y = g.origin.y();
  grid.info.origin.orientation.w = 1.0;
  grid.data.assign(g.data.begin(), g.data.end());
  return grid;
}

visualization_msgs::MarkerArray obstacleMarkers(const std::vector<hulls::Obstacle>& obstacles,
                                                const std::vector<int>& previous_ids, const std_msgs::Header& header) {
  return toMarkerArray(live::obstacleMarkers(obstacles, previous_ids), header);
}

visualization_msgs::MarkerArray occupiedCellMarkers(const std::vector<mapper::OccupiedVoxel>& voxels, double resolution,
                                                    const std_msgs::Header& header) {
  return toMarkerArray(live::occupiedCellMarkers(voxels, resolution, header.frame_id), header);
}

nav_msgs::OccupancyGrid projectedMap(const std::vector<hulls::Obstacle>& obstacles, double resolution, double min_z,
                                     double max_z, double margin, const std_msgs::Header& header) {
  return toOccupancyGrid(live::projectedGrid(obstacles, resolution, min_z, max_z, margin), header);
}

visualization_msgs::MarkerArray pathCheckMarkers(const std::vector<Eigen::Vector3d>& waypoints,
                                                 const collision::PathCheck& check, double line_width,
                                                 const std_msgs::Header& header) {
  return toMarkerArray(live::pathCheckMarkers(waypoints, check, line_width), header);
}

}  // namespace hullmap::ros1
