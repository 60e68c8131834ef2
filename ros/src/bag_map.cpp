#include "hullmap/ros1/bag_map.hpp"

#include <filesystem>
#include <set>
#include <system_error>

#include <console_bridge/console.h>
#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Path.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/Marker.h>

#include "hullmap/core/error.hpp"
#include "hullmap/ros1/messages.hpp"

namespace hullmap::ros1 {

namespace {

/// rosbag_storage also logs its errors to stderr through console_bridge; the exception says the same,
/// so the caller prints one line. Restores the previous level when done.
class QuietConsoleBridge {
 public:
  QuietConsoleBridge() : level_(console_bridge::getLogLevel()) {
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  }
  ~QuietConsoleBridge() { console_bridge::setLogLevel(level_); }
  QuietConsoleBridge(const QuietConsoleBridge&) = delete;
  QuietConsoleBridge& operator=(const QuietConsoleBridge&) = delete;

 private:
  console_bridge::LogLevel level_;
};

/// "<path>: not a readable ROS1 bag (<rosbag's words>; the file holds N bytes)": rosbag_storage's
/// exceptions name no offset, the size tells a truncated file from a damaged one.
std::string unreadable(const std::string& path, const std::string& what) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return path + ": not a readable ROS1 bag (rosbag_storage: " + what +
         (ec ? std::string(")") : "; the file holds " + std::to_string(size) + " bytes)");
}

/// Throws "<path>: no message on topic ..." unless the bag has `topic`.
void requireTopic(const rosbag::Bag& bag, const std::string& path, const std::string& topic) {
  rosbag::View all(bag);
  std::set<std::string> topics;
  for (const auto* connection : all.getConnections()) topics.insert(connection->topic);
  if (topics.count(topic)) return;
  std::string names;
  for (const auto& t : topics) names += (names.empty() ? "" : ", ") + t;
  throw Error(path + ": no message on topic " + topic + " (topics: " + (names.empty() ? "none" : names) + ")");
}

io::Keyframe keyframe(const std_msgs::Header& header, const geometry_msgs::Pose& pose) {
  io::Keyframe k;
  k.stamp = header.stamp.toSec();
  k.position = {pose.position.x, pose.position.y, pose.position.z};
  k.orientation = Eigen::Quaterniond(pose.orientation.w, pose.orientation.x, pose.orientation.y, pose.orientation.z);
  return k;
}

}  // namespace

std::vector<io::Keyframe> readBagKeyframes(const std::string& path, const std::string& topic) {
  const QuietConsoleBridge quiet;
  std::vector<io::Keyframe> keyframes;
  try {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Read);
    requireTopic(bag, path, topic);
    rosbag::View view(bag, rosbag::TopicQuery(topic));
    for (const rosbag::MessageInstance& m : view) {
      if (auto pose = m.instantiate<geometry_msgs::PoseStamped>()) {
        keyframes.push_back(keyframe(pose->header, pose->pose));
      } else if (auto trajectory = m.instantiate<nav_msgs::Path>()) {
        keyframes.clear();  // the last Path is the whole trajectory
        for (const auto& p : trajectory->poses) keyframes.push_back(keyframe(p.header, p.pose));
      } else {
        throw Error(path + ": topic " + topic + " carries " + m.getDataType() +
                    ", expected geometry_msgs/PoseStamped or nav_msgs/Path");
      }
    }
  } catch (const rosbag::BagException& e) {
    throw Error(unreadable(path, e.what()));
  } catch (const ::ros::Exception& e) {
    throw Error(unreadable(path, e.what()));
  }
  if (!live::normaliseKeyframes(keyframes)) {
    throw Error(path + ": topic " + topic + ": a keyframe pose is not finite or its quaternion is zero");
  }
  if (keyframes.empty()) throw Error(path + ": topic " + topic + " holds no pose");
  return keyframes;
}

BagMap readBagMap(const std::string& path, const std::string& topic) {
  BagMap map;
  const QuietConsoleBridge quiet;
  try {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Read);
    requireTopic(bag, path, topic);
    rosbag::View view(bag, rosbag::TopicQuery(topic));
    live::TopicMap topic_map;
    for (const rosbag::MessageInstance& m : view) {
      if (auto marker = m.instantiate<visualization_msgs::Marker>()) {
        topic_map.addMarker(m.getDataType(), markerKey(*marker), marker->points);
      } else if (auto cloud = m.instantiate<sensor_msgs::PointCloud2>()) {
        topic_map.addCloud(m.getDataType(), cloudLayout(*cloud), cloud->data.data(), cloud->data.size());
      } else {
        throw Error(path + ": topic " + topic + " carries " + m.getDataType() +
                    ", expected visualization_msgs/Marker or sensor_msgs/PointCloud2");
      }
    }
    map = topic_map.result();
  } catch (const rosbag::BagException& e) {
    throw Error(unreadable(path, e.what()));
  } catch (const ::ros::Exception& e) {
    throw Error(unreadable(path, e.what()));
  }
  return map;
}

}  // namespace hullmap::ros1
