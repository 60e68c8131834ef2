// hullmap_bag_reader BAG --topic T [--trajectory-topic K]: rosbag2's own reader over a ROS 2 bag (a
// directory, or its .db3 or .mcap file) for `hullmap build BAG --topic T`, which runs it and reads
// its standard output (live::writeBagTopics' stream). The map rule is live::TopicMap's, the node's.
// One line "hullmap: error: ..." on standard error and exit 2 when the bag cannot be read.
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <rcutils/logging.h>
#include <geometry_msgs/msg/pose_stamped.hpp>
#include <nav_msgs/msg/path.hpp>
#include <rclcpp/serialization.hpp>
#include <rclcpp/serialized_message.hpp>
#include <rosbag2_cpp/reader.hpp>
#include <rosbag2_storage/storage_filter.hpp>
#include <rosbag2_storage/storage_options.hpp>
#include <sensor_msgs/msg/point_cloud2.hpp>
#include <visualization_msgs/msg/marker.hpp>

#include "hullmap/core/error.hpp"
#include "hullmap/live/ros2_bag.hpp"
#include "hullmap/ros2/messages.hpp"

namespace {

using hullmap::Error;

constexpr const char* kMarker = "visualization_msgs/msg/Marker";
constexpr const char* kCloud = "sensor_msgs/msg/PointCloud2";
constexpr const char* kPose = "geometry_msgs/msg/PoseStamped";
constexpr const char* kPath = "nav_msgs/msg/Path";

/// What rosbag2 logged at WARN or above while reading: a storage plugin that meets damage (MCAP's
/// reader, say) logs it and reads on, so a logged problem makes the bag unreadable here.
std::vector<std::string>& problems() {
  static std::vector<std::string> logged;
  return logged;
}

void recordProblem(const rcutils_log_location_t*, int severity, const char*, rcutils_time_point_value_t,
                   const char* format, va_list* args) {
  if (severity < RCUTILS_LOG_SEVERITY_WARN) return;
  char text[1024];
  va_list copy;
  va_copy(copy, *args);
  std::vsnprintf(text, sizeof text, format, copy);
  va_end(copy);
  problems().emplace_back(text);
}

std::string unreadable(const std::string& path, const std::string& what) {
  return path + ": not a readable ROS 2 bag (rosbag2: " + what + ")";
}

template <typename T>
T deserialize(const rosbag2_storage::SerializedBagMessage& message) {
  T out;
  const rclcpp::SerializedMessage serialized(*message.serialized_data);
  rclcpp::Serialization<T>().deserialize_message(&serialized, &out);
  return out;
}

/// A bag file (not a directory) is opened with the storage its extension names.
rosbag2_storage::StorageOptions storageOptions(const std::string& path) {
  rosbag2_storage::StorageOptions options;
  options.uri = path;
  const std::string extension = std::filesystem::path(path).extension().string();
  if (!std::filesystem::is_directory(path)) options.storage_id = extension == ".mcap" ? "mcap" : "sqlite3";
  return options;
}

hullmap::live::BagTopics read(const std::string& path, const std::string& topic,
                              const std::optional<std::string>& trajectory_topic) {
  if (!std::filesystem::exists(path)) throw Error(path + ": no such file or directory");
  hullmap::live::BagTopics topics;
  std::map<std::string, std::string> types;
  try {
    rosbag2_cpp::Reader reader;
    reader.open(storageOptions(path));
    for (const auto& t : reader.get_all_topics_and_types()) types[t.name] = t.type;
    std::map<std::string, std::size_t> listed;  // messages the bag's metadata lists on each topic
    for (const auto& t : reader.get_metadata().topics_with_message_count) {
      listed[t.topic_metadata.name] = t.message_count;
    }
    for (const auto* wanted : {&topic, trajectory_topic ? &*trajectory_topic : nullptr}) {
      if (!wanted || types.count(*wanted)) continue;
      std::string names;
      for (const auto& [name, type] : types) names += (names.empty() ? "" : ", ") + name;
      throw Error(path + ": no message on topic " + *wanted + " (topics: " + (names.empty() ? "none" : names) + ")");
    }
    const std::string& map_type = types.at(topic);
    if (map_type != kMarker && map_type != kCloud) {
      throw Error(path + ": topic " + topic + " carries " + map_type + ", expected " + kMarker + " or " + kCloud);
    }
    if (trajectory_topic) {
      const std::string& pose_type = types.at(*trajectory_topic);
      if (pose_type != kPose && pose_type != kPath) {
        throw Error(path + ": topic " + *trajectory_topic + " carries " + pose_type + ", expected " + kPose + " or " +
                    kPath);
      }
      topics.keyframes.emplace();
    }
    std::map<std::string, std::size_t> counted;  // messages read on each topic
    rosbag2_storage::StorageFilter filter;
    filter.topics = {topic};
    if (trajectory_topic) filter.topics.push_back(*trajectory_topic);
    reader.set_filter(filter);
    hullmap::live::TopicMap map;
    while (reader.has_next()) {
      const auto message = reader.read_next();
      ++counted[message->topic_name];
      if (message->topic_name == topic) {
        if (map_type == kMarker) {
          const auto marker = deserialize<visualization_msgs::msg::Marker>(*message);
          map.addMarker(map_type, hullmap::ros2::markerKey(marker), marker.points);
        } else {
          const auto cloud = deserialize<sensor_msgs::msg::PointCloud2>(*message);
          map.addCloud(map_type, hullmap::ros2::cloudLayout(cloud), cloud.data.data(), cloud.data.size());
        }
      }
      if (trajectory_topic && message->topic_name == *trajectory_topic) {
        if (types.at(*trajectory_topic) == kPose) {
          const auto pose = deserialize<geometry_msgs::msg::PoseStamped>(*message);
          nav_msgs::msg::Path one;
          one.poses.push_back(pose);
          for (const auto& k : hullmap::ros2::keyframes(one)) topics.keyframes->push_back(k);
        } else {
          *topics.keyframes =
              hullmap::ros2::keyframes(deserialize<nav_msgs::msg::Path>(*message));  // the last holds all
        }
      }
    }
    topics.map = map.result();
    // A damaged bag can read as a shorter one (an MCAP chunk whose header is broken is skipped).
    for (const auto* wanted : {&topic, trajectory_topic ? &*trajectory_topic : nullptr}) {
      if (!wanted) continue;
      const std::size_t expected = listed.count(*wanted) ? listed.at(*wanted) : 0;
      if (counted[*wanted] < expected) {
        throw Error(unreadable(path, "read " + std::to_string(counted[*wanted]) + " of the " +
                                         std::to_string(expected) + " messages its metadata lists on " + *wanted));
      }
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(unreadable(path, e.what()));
  }
  if (!problems().empty()) throw Error(unreadable(path, problems().front()));
  if (topics.keyframes) {
    if (!hullmap::live::normaliseKeyframes(*topics.keyframes)) {
      throw Error(path + ": topic " + *trajectory_topic + ": a keyframe pose is not finite or its quaternion is zero");
    }
    if (topics.keyframes->empty()) throw Error(path + ": topic " + *trajectory_topic + " holds no pose");
  }
  return topics;
}

}  // namespace

int main(int argc, char** argv) {
  std::optional<std::string> bag, topic, trajectory_topic;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--topic" || arg == "--trajectory-topic") && i + 1 < argc) {
      (arg == "--topic" ? topic : trajectory_topic) = argv[++i];
    } else if (arg == "--ros-args") {
      break;  // ros2 run's own arguments
    } else if (!bag && arg.compare(0, 1, "-") != 0) {
      bag = arg;
    } else {
      bag.reset();
      break;
    }
  }
  if (!bag || !topic) {
    std::cerr << "usage: hullmap_bag_reader BAG --topic T [--trajectory-topic K]\n"
                 "Reads a ROS 2 bag for `hullmap build BAG --topic T`, which runs it; writes a binary stream.\n";
    return 2;
  }
  if (rcutils_logging_initialize() == RCUTILS_RET_OK) rcutils_logging_set_output_handler(recordProblem);
  try {
    const hullmap::live::BagTopics topics = read(*bag, *topic, trajectory_topic);
    hullmap::live::writeBagTopics(std::cout, topics);
    std::cout.flush();
    return std::cout ? 0 : 2;
  } catch (const Error& e) {
    std::cerr << "hullmap: error: " << e.what() << "\n";
    return 2;
  }
}
