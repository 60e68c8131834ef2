#pragma once

#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "hullmap/live/map_messages.hpp"

/// ROS 2 bags for `hullmap build BAG --topic T`, without ROS 2 in this library: the bag is read by
/// rosbag2's own reader in `hullmap_bag_reader`, a program of the ROS 2 package hullmap_ros2, found
/// in the sourced ROS 2 environment (AMENT_PREFIX_PATH, as `ros2 run` finds it); it writes what it
/// read to a pipe in the stream format below, which this library reads back.
namespace hullmap::live {

/// What a bag's topics hold, as the bag readers give it.
struct BagTopics {
  BagMap map;                                          ///< the map topic's last map (TopicMap's rule)
  std::optional<std::vector<io::Keyframe>> keyframes;  ///< the trajectory topic's poses, when asked
};

/// True when `path` looks like a ROS 2 bag: a directory holding metadata.yaml, or a file ending in
/// .db3 or .mcap (rosbag2's sqlite3 and MCAP storage).
bool isRos2Bag(const std::filesystem::path& path);

/// Writes `topics` in the reader's stream format: the line "hullmap bag topics 1", then
/// "type T", "messages N", "skipped N", "points N" lines, N points as 3 little-endian float64
/// each, "keyframes N" (or "keyframes none") and N keyframes as 8 float64 each (stamp in seconds,
/// x y z, quaternion x y z w), then "end". Exact: every double as its 8 bytes.
void writeBagTopics(std::ostream& out, const BagTopics& topics);

/// Reads what writeBagTopics wrote. Throws hullmap::Error "bag reader stream: ..." when it is not that.
BagTopics readBagTopics(std::istream& in);

/// hullmap_bag_reader of the first prefix in AMENT_PREFIX_PATH that has it
/// (PREFIX/lib/hullmap_ros2/hullmap_bag_reader), or nullopt.
std::optional<std::filesystem::path> findRos2BagReader();

/// Reads `topic` (and `trajectory_topic`, when given) of the ROS 2 bag at `path` with
/// hullmap_bag_reader: the map by TopicMap's rule, the keyframes as the ROS 1 bag reader takes them
/// (geometry_msgs/PoseStamped one a message, or nav_msgs/Path whose last message holds all).
/// Throws hullmap::Error with the reader's one-line message (naming the bag and topic), or
/// "<path>: a ROS 2 bag: reading it needs ... (not found in AMENT_PREFIX_PATH)" without the reader.
BagTopics readRos2Bag(const std::string& path, const std::string& topic,
                      const std::optional<std::string>& trajectory_topic);

}  // namespace hullmap::live
