#pragma once

#include <memory>
#include <set>
#include <string>

#include <hullmap_interfaces/srv/check_path.hpp>
#include <nav_msgs/msg/occupancy_grid.hpp>
#include <nav_msgs/msg/path.hpp>
#include <rclcpp/rclcpp.hpp>
#include <sensor_msgs/msg/point_cloud2.hpp>
#include <std_msgs/msg/string.hpp>
#include <std_srvs/srv/empty.hpp>
#include <std_srvs/srv/trigger.hpp>
#include <visualization_msgs/msg/marker.hpp>
#include <visualization_msgs/msg/marker_array.hpp>

#include "hullmap/live/node_params.hpp"
#include "hullmap/live/rebuild_worker.hpp"
#include "hullmap/ros2/map_input.hpp"
#include "hullmap/ros2/messages.hpp"

namespace hullmap::ros2 {

/// hullmap's live node for ROS 2, a composable node (rclcpp_components: hullmap::ros2::HullmapNode):
/// the SLAM map in, convex obstacles out, rebuilt on the newest map by live::RebuildWorker, the
/// rules shared with the ROS 1 node. Topics, QoS, parameters and services: docs/ROS.md.
/// The constructor throws hullmap::Error naming the parameter when a parameter's value is bad.
class HullmapNode : public rclcpp::Node {
 public:
  explicit HullmapNode(const rclcpp::NodeOptions& options = rclcpp::NodeOptions());
  ~HullmapNode() override;

 private:
  void declareParameters();
  rcl_interfaces::msg::SetParametersResult onSetParameters(const std::vector<rclcpp::Parameter>& parameters);

  void onMarker(const visualization_msgs::msg::Marker& msg);
  void onCloud(const sensor_msgs::msg::PointCloud2& msg);
  void onKeyframes(const nav_msgs::msg::Path& msg);
  void onPath(const nav_msgs::msg::Path& msg);
  void onCheckPath(const hullmap_interfaces::srv::CheckPath::Request& request,
                   hullmap_interfaces::srv::CheckPath::Response& response);
  void skip(const std::string& why);
  void subscribeMapInputs();
  void tellBestEffort(const std::string& topic, std::size_t publishers);  // once per input
  void onLost(const std::string& topic, std::size_t count, const InputQos& qos);
  std_msgs::msg::Header header(std::int64_t stamp_ns);
  void publishMap(const live::MapPublication& publication);
  std::vector<Eigen::Vector3d> waypoints(const nav_msgs::msg::Path& path);

  live::ParameterValues values_;                                // the parameters as set (parameter callbacks only)
  std::string frame_id_;                                        // read-only
  live::OrbSlamMapMarkers orbslam_;                             // the node's callbacks only
  std::shared_ptr<const std::vector<io::Keyframe>> keyframes_;  // the node's callbacks only

  rclcpp::Publisher<visualization_msgs::msg::MarkerArray>::SharedPtr obstacles_pub_, cells_pub_, path_markers_pub_;
  rclcpp::Publisher<nav_msgs::msg::OccupancyGrid>::SharedPtr grid_pub_;
  rclcpp::Publisher<std_msgs::msg::String>::SharedPtr stats_pub_, path_check_pub_;
  std::unique_ptr<live::RebuildWorker> worker_;  // after the publishers its hooks use
  std::unique_ptr<MapInput<visualization_msgs::msg::Marker>> marker_input_;
  std::unique_ptr<MapInput<sensor_msgs::msg::PointCloud2>> cloud_input_;
  std::unique_ptr<MapInput<nav_msgs::msg::Path>> keyframes_input_;
  rclcpp::TimerBase::SharedPtr follow_timer_;  // the map inputs follow their publishers' QoS
  std::set<std::string> lost_told_;            // inputs whose first lost message was logged
  std::set<std::string> best_effort_told_;     // inputs whose first best-effort publisher was logged
  rclcpp::Subscription<nav_msgs::msg::Path>::SharedPtr path_sub_;
  rclcpp::Service<std_srvs::srv::Trigger>::SharedPtr save_srv_;
  rclcpp::Service<std_srvs::srv::Empty>::SharedPtr reset_srv_;
  rclcpp::Service<hullmap_interfaces::srv::CheckPath>::SharedPtr check_path_srv_;
  rclcpp::node_interfaces::OnSetParametersCallbackHandle::SharedPtr parameters_callback_;
};

}  // namespace hullmap::ros2
