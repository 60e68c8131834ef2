#pragma once

#include <cstddef>
#include <string>

#include <vector>

#include "hullmap/io/point_cloud.hpp"
#include "hullmap/io/readers.hpp"
#include "hullmap/live/map_messages.hpp"

namespace hullmap::ros1 {

/// The map a ROS1 bag's topic ends on, as hullmap_node would hold it after replaying the bag.
using BagMap = live::BagMap;

/// Reads `topic` of the ROS1 bag at `path` (Debian's rosbag_storage) and returns its last map by
/// live::TopicMap's rule: for visualization_msgs/Marker the latest MapPoints id 0 plus id 6 (ORB-SLAM
/// v1's /ORB_SLAM/Map), for sensor_msgs/PointCloud2 the last cloud. Malformed messages (a MapPoints
/// marker with a NaN, a cloud without z) are skipped and counted, as the node does.
/// Throws hullmap::Error "<path>: not a readable ROS1 bag (rosbag_storage: <why>; the file holds N
/// bytes)" for a bag that cannot be opened or read (truncated; a damaged version line, record
/// header, chunk or index: ROS1 bags carry no checksum, so damage inside a message's bytes is not
/// seen), "<path>: no message on topic <topic> (topics: ...)" when the topic is absent, or when its
/// type is neither of the two. Not thread-safe: it silences console_bridge's log while it reads.
BagMap readBagMap(const std::string& path, const std::string& topic);

/// The keyframe poses (camera-to-map, the map topic's frame) on `topic` of the bag at `path`:
/// geometry_msgs/PoseStamped, one keyframe per message, in bag order; or nav_msgs/Path, whose last
/// message holds every keyframe (a SLAM system re-sends its whole keyframe trajectory). Stamps are
/// the headers' (a Path's poses' own). Throws hullmap::Error as readBagMap, and naming the topic
/// when it holds neither type or no pose.
std::vector<io::Keyframe> readBagKeyframes(const std::string& path, const std::string& topic);

}  // namespace hullmap::ros1
