#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <builtin_interfaces/msg/time.hpp>
#include <nav_msgs/msg/occupancy_grid.hpp>
#include <nav_msgs/msg/path.hpp>
#include <rclcpp/parameter.hpp>
#include <sensor_msgs/msg/point_cloud2.hpp>
#include <std_msgs/msg/header.hpp>
#include <visualization_msgs/msg/marker.hpp>
#include <visualization_msgs/msg/marker_array.hpp>

#include "hullmap/io/readers.hpp"
#include "hullmap/live/map_messages.hpp"
#include "hullmap/live/node_params.hpp"
#include "hullmap/live/outputs.hpp"

/// ROS 2 messages to and from hullmap::live's neutral types, for the ROS 2 node and its bag reader:
/// copies of fields, nothing more (the rules are live's, shared with the ROS 1 node). Reentrant.
namespace hullmap::ros2 {

/// A marker's key for live::OrbSlamMapMarkers (a view of its namespace).
live::MarkerKey markerKey(const visualization_msgs::msg::Marker& marker);

/// A cloud's layout for live::cloudPoints (views of its field names).
live::CloudLayout cloudLayout(const sensor_msgs::msg::PointCloud2& cloud);

/// The cloud's finite points (live::cloudPoints). Throws hullmap::Error as it does.
io::Points cloudPoints(const sensor_msgs::msg::PointCloud2& cloud, std::size_t* non_finite = nullptr);

/// A stamp in nanoseconds, and back (exact).
std::int64_t toNanoseconds(const builtin_interfaces::msg::Time& stamp);
builtin_interfaces::msg::Time toStamp(std::int64_t nanoseconds);

/// The poses of a Path as keyframes (stamps from the poses' headers, in seconds), unchecked.
std::vector<io::Keyframe> keyframes(const nav_msgs::msg::Path& path);

/// A neutral marker as a Marker with `header`.
visualization_msgs::msg::Marker toMarker(const live::MarkerSpec& spec, const std_msgs::msg::Header& header);

/// Neutral markers as a MarkerArray with `header`.
visualization_msgs::msg::MarkerArray toMarkerArray(const std::vector<live::MarkerSpec>& specs,
                                                   const std_msgs::msg::Header& header);

/// A neutral grid as an OccupancyGrid with `header` (map_load_time: the header's stamp).
nav_msgs::msg::OccupancyGrid toOccupancyGrid(const live::ProjectedGrid& grid, const std_msgs::msg::Header& header);

/// A parameter's value as live reads it (arrays as their text, which no parameter accepts); false
/// when the parameter is not set.
bool toParameterValue(const rclcpp::ParameterValue& value, live::ParameterValue& out);

/// A parameter's value for declaring it with its default.
rclcpp::ParameterValue toRclcppValue(const live::ParameterValue& value);

}  // namespace hullmap::ros2
