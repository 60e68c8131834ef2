#include "hullmap/ros2/messages.hpp"

#include <variant>

namespace hullmap::ros2 {
namespace {

geometry_msgs::msg::Point toPoint(const Eigen::Vector3d& v) {
  geometry_msgs::msg::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}

std_msgs::msg::ColorRGBA toColor(const live::Rgba& c) {
  std_msgs::msg::ColorRGBA color;
  color.r = c.r;
  color.g = c.g;
  color.b = c.b;
  color.a = c.a;
  return color;
}

}  // namespace

live::MarkerKey markerKey(const visualization_msgs::msg::Marker& m) { return {m.ns, m.id, m.type, m.action}; }

live::CloudLayout cloudLayout(const sensor_msgs::msg::PointCloud2& cloud) {
  live::CloudLayout layout;
  for (const auto& f : cloud.fields) layout.fields.push_back({f.name, f.offset, f.datatype});
  layout.width = cloud.width;
  layout.height = cloud.height;
  layout.point_step = cloud.point_step;
  layout.row_step = cloud.row_step;
  layout.is_bigendian = cloud.is_bigendian;
  return layout;
}

io::Points cloudPoints(const sensor_msgs::msg::PointCloud2& cloud, std::size_t* non_finite) {
  return live::cloudPoints(cloudLayout(cloud), cloud.data.data(), cloud.data.size(), non_finite);
}

std::int64_t toNanoseconds(const builtin_interfaces::msg::Time& stamp) {
  return std::int64_t{stamp.sec} * 1000000000 + stamp.nanosec;
}

builtin_interfaces::msg::Time toStamp(std::int64_t nanoseconds) {
  builtin_interfaces::msg::Time stamp;
  stamp.sec = static_cast<std::int32_t>(nanoseconds / 1000000000);
  stamp.nanosec = static_cast<std::uint32_t>(nanoseconds % 1000000000);
  return stamp;
}

std::vector<io::Keyframe> keyframes(const nav_msgs::msg::Path& path) {
  std::vector<io::Keyframe> out;
  out.reserve(path.poses.size());
  for (const auto& p : path.poses) {
    io::Keyframe k;
    k.stamp = p.header.stamp.sec + 1e-9 * p.header.stamp.nanosec;  // as ROS 1's Time::toSec
    k.position = {p.pose.position.x, p.pose.position.y, p.pose.position.z};
    const auto& o = p.pose.orientation;
    k.orientation = Eigen::Quaterniond(o.w, o.x, o.y, o.z);
    out.push_back(k);
  }
  return out;
}

visualization_msgs::msg::Marker toMarker(const live::MarkerSpec& spec, const std_msgs::msg::Header& header) {
  visualization_msgs::msg::Marker m;
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

visualization_msgs::msg::MarkerArray toMarkerArray(const std::vector<live::MarkerSpec>& specs,
                                                   const std_msgs::msg::Header& header) {
  visualization_msgs::msg::MarkerArray array;
  array.markers.reserve(specs.size());
  for (const auto& spec : specs) array.markers.push_back(toMarker(spec, header));
  return array;
}

nav_msgs::msg::OccupancyGrid toOccupancyGrid(const live::ProjectedGrid& g, const std_msgs::msg::Header& header) {
  nav_msgs::msg::OccupancyGrid grid;
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

bool toParameterValue(const rclcpp::ParameterValue& value, live::ParameterValue& out) {
  switch (value.get_type()) {
    case rclcpp::ParameterType::PARAMETER_NOT_SET:
      return false;
    case rclcpp::ParameterType::PARAMETER_BOOL:
      out = value.get<bool>();
      return true;
    case rclcpp::ParameterType::PARAMETER_INTEGER:
      out = std::int64_t{value.get<std::int64_t>()};
      return true;
    case rclcpp::ParameterType::PARAMETER_DOUBLE:
      out = value.get<double>();
      return true;
    case rclcpp::ParameterType::PARAMETER_STRING:
      out = value.get<std::string>();
      return true;
    default:
      out = rclcpp::to_string(value);
      return true;
  }
}

rclcpp::ParameterValue toRclcppValue(const live::ParameterValue& value) {
  return std::visit([](const auto& v) { return rclcpp::ParameterValue(v); }, value);
}

}  // namespace hullmap::ros2
