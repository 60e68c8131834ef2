// hullmap_node: the SLAM map in, convex obstacles out, rebuilt in a worker thread on the newest map.
// See docs/ROS.md for topics, parameters and services.
#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
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

#include <nlohmann/json.hpp>

#include "hullmap/collision/path_check.hpp"
#include "hullmap/core/error.hpp"
#include "hullmap/pipeline/check_json.hpp"
#include "hullmap/pipeline/pipeline.hpp"
#include "hullmap/ros1/messages.hpp"
#include "hullmap/ros1/node_params.hpp"

namespace hullmap::ros1 {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

/// A map waiting for the worker: the newest one replaces it (folded) before the worker takes it.
struct PendingMap {
  mapper::Points points;
  ::ros::Time stamp;
  Clock::time_point received;
  std::shared_ptr<const std::vector<mapper::Keyframe>> keyframes;  ///< null: points-only octree
  /// ORB-SLAM's map markers are in its first camera's frame (levelled under ~level auto); a cloud is
  /// judged as a file is (its up axis).
  std::optional<bool> camera_frame;
};

/// A finished rebuild, shared between the worker (writes) and the services (read).
struct Snapshot {
  pipeline::BuildResult result;
  collision::HullChecker checker;
};

class HullmapNode {
 public:
  HullmapNode(::ros::NodeHandle& nh, ::ros::NodeHandle& pnh)
      : build_params_(readBuildParams(pnh)), params_(readNodeParams(pnh)) {
    obstacles_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("obstacles", 1, true);
    cells_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("occupied_cells_vis_array", 1, true);
    grid_pub_ = pnh.advertise<nav_msgs::OccupancyGrid>("projected_map", 1, true);
    stats_pub_ = pnh.advertise<std_msgs::String>("stats", 1, true);
    path_check_pub_ = pnh.advertise<std_msgs::String>("path_check", 10, true);
    path_markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("path_check_markers", 1, true);
    // Queue 2: the map topics re-send the whole map, so an older message is never needed.
    marker_sub_ = nh.subscribe("/ORB_SLAM/Map", 20, &HullmapNode::onMarker, this);
    cloud_sub_ = pnh.subscribe("cloud_in", 2, &HullmapNode::onCloud, this);
    path_sub_ = pnh.subscribe("check_path", 10, &HullmapNode::onPath, this);
    keyframes_sub_ = pnh.subscribe("keyframes", 2, &HullmapNode::onKeyframes, this);
    save_srv_ = pnh.advertiseService("save", &HullmapNode::onSave, this);
    reset_srv_ = pnh.advertiseService("reset", &HullmapNode::onReset, this);
    publishStats();
    worker_ = std::thread([this] { run(); });
  }

  ~HullmapNode() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    worker_.join();
  }

 private:
  void onMarker(const visualization_msgs::Marker::ConstPtr& msg) {
    try {
      if (!orbslam_.add(*msg)) return;
    } catch (const Error& e) {
      skip(std::string("/ORB_SLAM/Map: ") + e.what());
      return;
    }
    submit({orbslam_.points(), msg->header.stamp, Clock::now(), keyframes_, true});
  }

  /// The whole keyframe trajectory (the last Path replaces the previous one); used from the next map on.
  void onKeyframes(const nav_msgs::Path::ConstPtr& msg) {
    auto keyframes = std::make_shared<std::vector<mapper::Keyframe>>();
    for (const auto& p : msg->poses) {
      mapper::Keyframe k;
      k.stamp = p.header.stamp.toSec();
      k.position = {p.pose.position.x, p.pose.position.y, p.pose.position.z};
      const auto& o = p.pose.orientation;
      k.orientation = Eigen::Quaterniond(o.w, o.x, o.y, o.z);
      if (!k.position.allFinite() || !k.orientation.coeffs().allFinite() || k.orientation.norm() < 1e-9) {
        skip("~keyframes: a pose is not finite or its quaternion is zero");
        return;
      }
      k.orientation.normalize();
      keyframes->push_back(k);
    }
    if (keyframes->empty()) keyframes.reset();
    keyframes_ = std::move(keyframes);
  }

  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
    const auto received = Clock::now();
    try {
      std::size_t non_finite = 0;
      mapper::Points points = cloudPoints(*msg, &non_finite);
      if (non_finite > 0) ROS_DEBUG("~cloud_in: %zu points with a non-finite coordinate skipped", non_finite);
      submit({std::move(points), msg->header.stamp, received, keyframes_, std::nullopt});
    } catch (const Error& e) {
      skip(std::string("~cloud_in: ") + e.what());
    }
  }

  void skip(const std::string& why) {
    ROS_WARN("hullmap: message skipped: %s", why.c_str());
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++skipped_;
    }
    publishStats();
  }

  /// Never blocks on a rebuild: the map replaces any map still waiting, and the worker is woken.
  void submit(PendingMap map) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++messages_;
      if (pending_) ++folded_;
      pending_ = std::move(map);
      max_waiting_ = std::max<std::uint64_t>(max_waiting_, pending_ ? 1 : 0);
    }
    wake_.notify_one();
  }

  void run() {
    std::optional<Clock::time_point> last_start;
    for (;;) {
      PendingMap map;
      std::uint64_t generation = 0;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [this] { return stop_ || pending_.has_value(); });
        if (stop_) return;
        if (last_start) {
          const auto earliest = *last_start + std::chrono::duration_cast<Clock::duration>(
                                                  std::chrono::duration<double>(params_.min_interval));
          if (wake_.wait_until(lock, earliest, [this] { return stop_; })) return;
          if (!pending_) continue;  // reset meanwhile
        }
        map = std::move(*pending_);
        pending_.reset();
        generation = generation_;
        busy_ = true;
      }
      last_start = Clock::now();
      rebuild(std::move(map), generation);
    }
  }

  void rebuild(PendingMap map, std::uint64_t generation) {
    const auto start = Clock::now();
    std::shared_ptr<Snapshot> snapshot;
    std::string failure;
    const std::size_t points = map.points.size();
    if (!map.points.empty()) {
      try {
        pipeline::BuildParams params = build_params_;
        if (!params.camera_frame) params.camera_frame = map.camera_frame;
        pipeline::BuildResult result =
            map.keyframes ? pipeline::buildFromPoints(std::move(map.points), *map.keyframes, params, "map",
                                                      "~keyframes")
                          : pipeline::buildFromPoints(std::move(map.points), params, "map");
        // The floor and ceiling found are obstacles for ~check_path, as for `hullmap check`.
        collision::HullChecker checker(result.obstacles, result.surfaces);
        snapshot = std::make_shared<Snapshot>(Snapshot{std::move(result), std::move(checker)});
      } catch (const std::exception& e) {
        failure = e.what();
      }
    }
    const double rebuild_ms = msSince(start);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      busy_ = false;
      if (generation != generation_) return;  // reset while it ran
      if (!failure.empty()) {
        ++failed_;
      } else {
        ++rebuilds_;
        latest_ = snapshot;
        last_points_ = points;
        last_rebuild_ms_ = rebuild_ms;
      }
    }
    if (!failure.empty()) {
      ROS_ERROR("hullmap: rebuild of %zu points failed: %s", points, failure.c_str());
      publishStats();
      return;
    }
    publishMap(snapshot, map.stamp, generation);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      last_latency_ms_ = msSince(map.received);
    }
    publishStats();
  }

  std_msgs::Header header(const ::ros::Time& stamp) const {
    std_msgs::Header h;
    h.frame_id = params_.frame_id;
    h.stamp = stamp.isZero() ? ::ros::Time::now() : stamp;
    return h;
  }

  /// Publishes a snapshot (nullptr: the empty map) unless a ~reset came after `generation` began. Only
  /// the worker and ~reset call it, one at a time.
  void publishMap(const std::shared_ptr<Snapshot>& snapshot, const ::ros::Time& stamp, std::uint64_t generation) {
    std::lock_guard<std::mutex> lock(publish_mutex_);
    {
      std::lock_guard<std::mutex> state(mutex_);
      if (generation != generation_) return;
    }
    const std_msgs::Header h = header(stamp);
    static const std::vector<clustering::Obstacle> kNone;
    static const std::vector<mapper::OccupiedVoxel> kNoVoxels;
    const auto& obstacles = snapshot ? snapshot->result.obstacles : kNone;
    obstacles_pub_.publish(obstacleMarkers(obstacles, published_ids_, h));
    published_ids_.clear();
    for (const auto& o : obstacles) published_ids_.push_back(o.id);
    cells_pub_.publish(occupiedCellMarkers(snapshot ? snapshot->result.voxels : kNoVoxels,
                                           build_params_.octree.resolution, h));
    grid_pub_.publish(projectedMap(obstacles, build_params_.octree.resolution, params_.occupancy_min_z,
                                   params_.occupancy_max_z, 2 * build_params_.octree.resolution, h));
  }

  void publishStats() {
    nlohmann::json j;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      j = {{"messages", messages_},
           {"skipped", skipped_},
           {"folded", folded_},
           {"rebuilds", rebuilds_},
           {"failed", failed_},
           {"max_waiting", max_waiting_},
           {"pending", pending_ ? 1 : 0},
           {"busy", busy_},
           {"points", last_points_},
           {"keyframes", latest_ ? latest_->result.report.keyframes : 0},
           {"voxels", latest_ ? latest_->result.voxels.size() : 0},
           {"obstacles", latest_ ? latest_->result.obstacles.size() : 0},
           {"rebuild_ms", last_rebuild_ms_},
           {"latency_ms", last_latency_ms_}};
    }
    std_msgs::String msg;
    msg.data = j.dump();
    stats_pub_.publish(msg);
  }

  void onPath(const nav_msgs::Path::ConstPtr& msg) {
    std::shared_ptr<Snapshot> snapshot;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      snapshot = latest_;
    }
    if (msg->poses.empty()) {
      ROS_WARN("hullmap: ~check_path: a path without poses, skipped");
      return;
    }
    if (!msg->header.frame_id.empty() && msg->header.frame_id != params_.frame_id) {
      ROS_WARN("hullmap: ~check_path: path in frame %s, checked as if in %s (no tf lookup)",
               msg->header.frame_id.c_str(), params_.frame_id.c_str());
    }
    std::vector<Eigen::Vector3d> waypoints;
    for (const auto& p : msg->poses) waypoints.emplace_back(p.pose.position.x, p.pose.position.y, p.pose.position.z);
    collision::PathCheck check;
    try {
      if (snapshot) {
        check = snapshot->checker.checkPath(waypoints, params_.radius);
      } else {
        check = collision::HullChecker(std::vector<clustering::Obstacle>{}).checkPath(waypoints, params_.radius);
      }
    } catch (const Error& e) {
      ROS_WARN("hullmap: ~check_path: %s; skipped", e.what());
      return;
    }
    std_msgs::String lines;
    for (std::size_t i = 0; i < check.segments.size(); ++i) {
      lines.data += pipeline::segmentCheckJsonLine(i, check.segments[i]) + "\n";
    }
    path_check_pub_.publish(lines);
    path_markers_pub_.publish(pathCheckMarkers(waypoints, check, 0.05, header(msg->header.stamp)));
  }

  bool onSave(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    std::shared_ptr<Snapshot> snapshot;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      snapshot = latest_;
    }
    if (!snapshot) {
      res.success = false;
      res.message = "no map built yet";
      return true;
    }
    try {
      pipeline::write(snapshot->result, params_.output_dir, {true});
      res.success = true;
      res.message = std::filesystem::absolute(params_.output_dir).string();
    } catch (const std::exception& e) {
      res.success = false;
      res.message = e.what();
    }
    return true;
  }

  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    orbslam_.clear();
    keyframes_.reset();
    std::uint64_t generation = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      pending_.reset();
      generation = ++generation_;
      latest_.reset();
      last_points_ = 0;
    }
    publishMap(nullptr, ::ros::Time::now(), generation);
    publishStats();
    return true;
  }

  const pipeline::BuildParams build_params_;
  const NodeParams params_;
  OrbSlamMapMarkers orbslam_;  // callback thread only
  std::shared_ptr<const std::vector<mapper::Keyframe>> keyframes_;  // callback thread only

  ::ros::Publisher obstacles_pub_, cells_pub_, grid_pub_, stats_pub_, path_check_pub_, path_markers_pub_;
  ::ros::Subscriber marker_sub_, cloud_sub_, path_sub_, keyframes_sub_;
  ::ros::ServiceServer save_srv_, reset_srv_;

  std::mutex mutex_;  // guards what follows
  std::condition_variable wake_;
  std::optional<PendingMap> pending_;
  bool stop_ = false;
  bool busy_ = false;
  std::uint64_t generation_ = 0;
  std::shared_ptr<Snapshot> latest_;
  std::uint64_t messages_ = 0, skipped_ = 0, folded_ = 0, rebuilds_ = 0, failed_ = 0;
  std::uint64_t max_waiting_ = 0;  // most maps ever waiting for the worker at once
  std::size_t last_points_ = 0;
  double last_rebuild_ms_ = 0.0, last_latency_ms_ = 0.0;

  std::mutex publish_mutex_;  // guards published_ids_ and the order of map publications
  std::vector<int> published_ids_;

  std::thread worker_;
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
