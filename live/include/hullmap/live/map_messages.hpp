#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hullmap/core/error.hpp"
#include "hullmap/io/point_cloud.hpp"
#include "hullmap/io/readers.hpp"

/// The contents of map messages turned into points, for both ROS nodes and both bag readers. No ROS
/// type appears here: a front end passes a message's fields (a PointCloud2's layout and bytes, a
/// Marker's namespace, id, type, action and points). Coordinates are taken as they are (the input
/// frame). Functions are reentrant; the classes are not thread-safe.
namespace hullmap::live {

/// sensor_msgs/PointField datatypes (the same in ROS 1 and ROS 2).
inline constexpr std::uint8_t kFloat32 = 7;
inline constexpr std::uint8_t kFloat64 = 8;

/// One field of a PointCloud2 (a view of the message's name: it must outlive the call).
struct CloudField {
  std::string_view name;
  std::uint32_t offset = 0;
  std::uint8_t datatype = 0;
};

/// A PointCloud2's header fields, without its data.
struct CloudLayout {
  std::vector<CloudField> fields;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t point_step = 0;  ///< bytes
  std::uint32_t row_step = 0;    ///< bytes
  bool is_bigendian = false;
};

/// The x, y and z fields of every point of a cloud (FLOAT32 or FLOAT64 fields, little-endian), in
/// point order; `data` holds the message's `size` bytes. Points with a NaN or infinite coordinate
/// (the holes of an organised cloud) are skipped and counted in `*non_finite` when given. Throws
/// hullmap::Error when a field is missing ("PointCloud2: no field z"), of another type, lies beyond
/// point_step, or the data is shorter than its header says.
io::Points cloudPoints(const CloudLayout& layout, const std::uint8_t* data, std::size_t size,
                       std::size_t* non_finite = nullptr);

/// visualization_msgs/Marker's types and actions (the same in ROS 1 and ROS 2).
namespace marker {
inline constexpr int kLineStrip = 4;
inline constexpr int kLineList = 5;
inline constexpr int kCubeList = 6;
inline constexpr int kPoints = 8;
inline constexpr int kTextViewFacing = 9;
inline constexpr int kTriangleList = 11;
inline constexpr int kAdd = 0;
inline constexpr int kDelete = 2;
inline constexpr int kDeleteAll = 3;
}  // namespace marker

/// What identifies a Marker and what it asks (a view of the message's namespace).
struct MarkerKey {
  std::string_view ns;
  int id = 0;
  int type = 0;
  int action = marker::kAdd;
};

/// ORB-SLAM (v1)'s map as its MapPublisher sends it on /ORB_SLAM/Map: namespace "MapPoints", id 0
/// all map points and id 6 the reference points, each a POINTS marker re-sent whole; the map is the
/// latest id 0 plus the latest id 6, exactly as `hullmap build` reads a `rostopic echo` dump
/// (DELETE drops one of them, DELETEALL both; other namespaces and ids are keyframes and graph
/// lines, not map points). Not thread-safe.
class OrbSlamMapMarkers {
 public:
  /// Takes one marker: its key and its points (a range of anything with members x, y and z, as a
  /// Marker's points); true when the map changed. Throws hullmap::Error naming the marker
  /// ("MapPoints id 0: point 12 is not finite") when a map-points marker holds a NaN or infinite
  /// coordinate; the map is then left as it was.
  template <typename PointRange>
  bool add(const MarkerKey& key, const PointRange& points);
  /// The map: the id 0 points, then the id 6 points (input frame).
  io::Points points() const;
  /// True before any map-points marker (or after a DELETEALL).
  bool empty() const { return !all_ && !reference_; }
  void clear();

 private:
  /// What `key` does to the map without its points: the answer of add() when it is decided here
  /// (not a map-points ADD), else nullopt and `*slot` is the marker to replace.
  std::optional<bool> decide(const MarkerKey& key, std::optional<io::Points>** slot);

  std::optional<io::Points> all_;        ///< id 0
  std::optional<io::Points> reference_;  ///< id 6
};

template <typename PointRange>
bool OrbSlamMapMarkers::add(const MarkerKey& key, const PointRange& points) {
  std::optional<io::Points>* slot = nullptr;
  if (const auto decided = decide(key, &slot)) return *decided;
  io::Points taken;
  taken.reserve(std::size(points));
  std::size_t i = 0;
  for (const auto& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw Error("MapPoints id " + std::to_string(key.id) + ": point " + std::to_string(i) + " is not finite");
    }
    taken.emplace_back(p.x, p.y, p.z);
    ++i;
  }
  *slot = std::move(taken);
  return true;
}

/// The map a topic of a bag ends on, as a node would hold it after the topic was replayed into it.
struct BagMap {
  io::Points points;         ///< input frame (the topic's), in message order
  std::string type;          ///< the topic's message type, as the bag names it
  std::size_t messages = 0;  ///< messages read on the topic
  std::size_t skipped = 0;   ///< malformed messages skipped (as the node skips them)
};

/// The node's map rule over a topic's messages in order, for the bag readers: for Markers the
/// latest MapPoints id 0 plus id 6 (OrbSlamMapMarkers), for PointCloud2 the last well-formed cloud
/// (each is the whole map); a malformed message is skipped and counted, as the node skips it.
class TopicMap {
 public:
  template <typename PointRange>
  void addMarker(const std::string& type, const MarkerKey& key, const PointRange& points) {
    count(type);
    try {
      markers_.add(key, points);
    } catch (const Error&) {
      ++map_.skipped;
    }
  }
  void addCloud(const std::string& type, const CloudLayout& layout, const std::uint8_t* data, std::size_t size);
  /// The map after the messages given so far.
  BagMap result() const;

 private:
  void count(const std::string& type);

  BagMap map_;
  OrbSlamMapMarkers markers_;
  bool clouds_ = false;
};

/// Messages a subscription never got, from the gaps in each publisher's sequence numbers (1, 2, ...
/// per publisher, as DDS numbers a writer's samples): what the transport lost, or a full queue
/// dropped, told when the next message of that publisher arrives. Not thread-safe.
class SequenceGaps {
 public:
  /// Messages of `publisher` (any id that names it, a GID's bytes) missed between its last message
  /// seen here and this one, numbered `sequence`; 0 for its first, and for one not newer.
  std::uint64_t missed(const std::string& publisher, std::uint64_t sequence);
  /// Forgets every publisher (a new subscription starts counting afresh).
  void clear() { last_.clear(); }

 private:
  std::map<std::string, std::uint64_t> last_;
};

/// Keyframe poses as a topic gave them, checked: false (and `keyframes` left as given) when a
/// position or quaternion is not finite or a quaternion is zero; else true, quaternions normalised.
bool normaliseKeyframes(std::vector<io::Keyframe>& keyframes);

}  // namespace hullmap::live
