// hullmap_node: the SLAM map in, convex obstacles out, rebuilt in a worker thread on the newest map.
// The ROS1 front end of live::RebuildWorker: it converts messages and publishes what the worker
// gives it. See docs/ROS.md for topics, parameters and services.
#include <memory>
#include <string>
#include <vector>

#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/String.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>
#include <visualization_msgs/Marker.h>
#include <visualization_msgs/MarkerArray.h>

#include "hullmap/core/error.hpp"
#include "hullmap/live/rebuild_worker.hpp"
#include "hullmap/ros1/messages.hpp"
#include "hullmap/ros1/node_params.hpp"

namespace hullmap::ros1 {
namespace {

class HullmapNode {
 public:
  HullmapNode(::ros::NodeHandle& nh, ::ros::NodeHandle& pnh) : HullmapNode(nh, pnh, readSettings(pnh)) {}

 private:
  HullmapNode(::ros::NodeHandle& nh, ::ros::NodeHandle& pnh, const live::NodeSettings& settings)
      : frame_id_(settings.node.frame_id) {
    obstacles_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("obstacles", 1, true);
    cells_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("occupied_cells_vis_array", 1, true);
    grid_pub_ = pnh.advertise<nav_msgs::OccupancyGrid>("projected_map", 1, true);
    stats_pub_ = pnh.advertise<std_msgs::String>("stats", 1, true);
    path_check_pub_ = pnh.advertise<std_msgs::String>("path_check", 10, true);
    path_markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("path_check_markers", 1, true);
    live::RebuildWorker::Hooks hooks;
    hooks.publish_map = [this](const live::MapPublication& p) { publishMap(p); };
    hooks.publish_stats = [this](const std::string& json) {
      std_msgs::String msg;
      msg.data = json;
      stats_pub_.publish(msg);
    };
    hooks.rebuild_failed = [](const std::string& why) { ROS_ERROR("hullmap: %s", why.c_str()); };
    worker_ = std::make_unique<live::RebuildWorker>(settings, std::move(hooks), "~keyframes");
    // Queue 2: the map topics re-send the whole map, so an older message is never needed.
    marker_sub_ = nh.subscribe("/ORB_SLAM/Map", 20, &HullmapNode::onMarker, this);
    cloud_sub_ = pnh.subscribe("cloud_in", 2, &HullmapNode::onCloud, this);
    path_sub_ = pnh.subscribe("check_path", 10, &HullmapNode::onPath, this);
    keyframes_sub_ = pnh.subscribe("keyframes", 2, &HullmapNode::onKeyframes, this);
    save_srv_ = pnh.advertiseService("save", &HullmapNode::onSave, this);
    reset_srv_ = pnh.advertiseService("reset", &HullmapNode::onReset, this);
  }

  void onMarker(const visualization_msgs::Marker::ConstPtr& msg) {
    try {
      if (!orbslam_.add(*msg)) return;
    } catch (const Error& e) {
      skip(std::string("/ORB_SLAM/Map: ") + e.what());
      return;
    }
    worker_->submit(
        {orbslam_.points(), std::int64_t(msg->header.stamp.toNSec()), live::Clock::now(), keyframes_, true});
  }

  /// The whole keyframe trajectory (the last Path replaces the previous one); used from the next map on.
  void onKeyframes(const nav_msgs::Path::ConstPtr& msg) {
    auto keyframes = std::make_shared<std::vector<io::Keyframe>>();
    for (const auto& p : msg->poses) {
      io::Keyframe k;
      k.stamp = p.header.stamp.toSec();
      k.position = {p.pose.position.x, p.pose.position.y, p.pose.position.z};
      const auto& o = p.pose.orientation;
      k.orientation = Eigen::Quaterniond(o.w, o.x, o.y, o.z);
      keyframes->push_back(k);
    }
    if (!live::normaliseKeyframes(*keyframes)) {
      skip("~keyframes: a pose is not finite or its quaternion is zero");
      return;
    }
    if (keyframes->empty()) keyframes.reset();
    keyframes_ = std::move(keyframes);
  }

  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
    const auto received = live::Clock::now();
    try {
      std::size_t non_finite = 0;
      io::Points points = cloudPoints(*msg, &non_finite);
      if (non_finite > 0) ROS_DEBUG("~cloud_in: %zu points with a non-finite coordinate skipped", non_finite);
      worker_->submit(
          {std::move(points), std::int64_t(msg->header.stamp.toNSec()), received, keyframes_, std::nullopt});
    } catch (const Error& e) {
      skip(std::string("~cloud_in: ") + e.what());
    }
  }

  void skip(const std::string& why) {
    ROS_WARN("hullmap: message skipped: %s", why.c_str());
    worker_->skip(why);
  }

  std_msgs::Header header(std::int64_t stamp_ns) const {
    std_msgs::Header h;
    h.frame_id = frame_id_;
    if (stamp_ns == 0) {
      h.stamp = ::ros::Time::now();
    } else {
      h.stamp.fromNSec(std::uint64_t(stamp_ns));
    }
    return h;
  }

  /// Called by the worker (and by ~reset), one at a time.
  void publishMap(const live::MapPublication& p) {
    const std_msgs::Header h = header(p.stamp_ns);
    obstacles_pub_.publish(toMarkerArray(p.obstacles, h));
    cells_pub_.publish(toMarkerArray(p.occupied_cells, h));
    grid_pub_.publish(toOccupancyGrid(p.projected_map, h));
  }

  void onPath(const nav_msgs::Path::ConstPtr& msg) {
    if (msg->poses.empty()) {
      ROS_WARN("hullmap: ~check_path: a path without poses, skipped");
      return;
    }
    if (!msg->header.frame_id.empty() && msg->header.frame_id != frame_id_) {
      ROS_WARN("hullmap: ~check_path: path in frame %s, checked as if in %s (no tf lookup)",
               msg->header.frame_id.c_str(), frame_id_.c_str());
    }
    std::vector<Eigen::Vector3d> waypoints;
    for (const auto& p : msg->poses) waypoints.emplace_back(p.pose.position.x, p.pose.position.y, p.pose.position.z);
    live::PathCheckAnswer answer;
    try {
      answer = worker_->checkPath(waypoints);
    } catch (const Error& e) {
      ROS_WARN("hullmap: ~check_path: %s; skipped", e.what());
      return;
    }
    std_msgs::String lines;
    lines.data = answer.json_lines;
    path_check_pub_.publish(lines);
    path_markers_pub_.publish(toMarkerArray(answer.markers, header(std::int64_t(msg->header.stamp.toNSec()))));
  }

  bool onSave(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    const live::SaveAnswer answer = worker_->save();
    res.success = answer.success;
    res.message = answer.message;
    return true;
  }

  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    orbslam_.clear();
    keyframes_.reset();
    worker_->reset();
    return true;
  }

  const std::string frame_id_;
  OrbSlamMapMarkers orbslam_;                                   // callback thread only
  std::shared_ptr<const std::vector<io::Keyframe>> keyframes_;  // callback thread only

  ::ros::Publisher obstacles_pub_, cells_pub_, grid_pub_, stats_pub_, path_check_pub_, path_markers_pub_;
  std::unique_ptr<live::RebuildWorker> worker_;  // after the publishers its hooks use, before the subscribers
  ::ros::Subscriber marker_sub_, cloud_sub_, path_sub_, keyframes_sub_;
  ::ros::ServiceServer save_srv_, reset_srv_;
};

}  // namespace
}  // namespace hullmap::ros1

int main(int argc, char** argv) {
  ::ros::init(argc, argv, "hullmap");
  ::ros::NodeHandle nh;
  ::ros::NodeHandle pnh("~");
  try {
    hullmap::ros1::HullmapNode node(nh, pnh);
    ::ros::spin();
  } catch (const hullmap::Error& e) {
    ROS_FATAL("hullmap: %s", e.what());
    return 2;
  }
  return 0;
}
