// hullmap's ROS 2 node: a front end of live::RebuildWorker that converts messages and publishes what
// the worker gives it. See docs/ROS.md for topics, QoS, parameters and services.
#include "hullmap/ros2/hullmap_node.hpp"

#include <chrono>
#include <limits>

#include <rclcpp_components/register_node_macro.hpp>

#include "hullmap/core/error.hpp"

namespace hullmap::ros2 {
namespace {

/// Outputs: reliable, transient_local, depth 1 (ROS 2's latching): a late subscriber gets the last.
rclcpp::QoS latched() { return rclcpp::QoS(1).reliable().transient_local(); }

/// ~/check_path: best effort, which takes both reliable and best-effort publishers.
rclcpp::QoS input(std::size_t depth) { return rclcpp::QoS(depth).best_effort(); }

/// How often the map inputs compare their QoS with their publishers' (rosbag2 polls at 100 ms).
constexpr std::chrono::milliseconds kFollowPeriod{100};

rcl_interfaces::msg::ParameterDescriptor descriptor(const live::ParameterSpec& spec) {
  rcl_interfaces::msg::ParameterDescriptor d;
  d.name = spec.name;
  d.description = spec.description;
  d.additional_constraints =
      spec.constraints + (spec.live ? "; may change while the node runs (the next rebuild, check or save uses it)"
                                    : "; set at start only");
  d.read_only = !spec.live;
  // Numbers may come as integers (`ros2 param set ... radius 1`), words or numbers as either, and
  // YAML reads extension's on and off as true and false: the node checks the value
  // (live::readSettings), rclcpp the range of a value of the range's type.
  d.dynamic_typing = spec.kind != live::ParameterKind::kText;
  const bool bounded =
      spec.min > -std::numeric_limits<double>::infinity() || spec.max < std::numeric_limits<double>::infinity();
  if (bounded && spec.whole) {
    rcl_interfaces::msg::IntegerRange range;
    range.from_value = static_cast<std::int64_t>(spec.min);
    range.to_value = static_cast<std::int64_t>(spec.max);
    range.step = 1;
    d.integer_range.push_back(range);
  } else if (bounded) {
    rcl_interfaces::msg::FloatingPointRange range;
    range.from_value = spec.min;
    range.to_value = spec.max;
    range.step = 0.0;
    d.floating_point_range.push_back(range);
  }
  return d;
}

}  // namespace

HullmapNode::HullmapNode(const rclcpp::NodeOptions& options) : rclcpp::Node("hullmap", options) {
  declareParameters();
  const live::NodeSettings settings = live::readSettings(values_, live::Checking::kStrict);
  frame_id_ = settings.node.frame_id;

  obstacles_pub_ = create_publisher<visualization_msgs::msg::MarkerArray>("~/obstacles", latched());
  cells_pub_ = create_publisher<visualization_msgs::msg::MarkerArray>("~/occupied_cells_vis_array", latched());
  grid_pub_ = create_publisher<nav_msgs::msg::OccupancyGrid>("~/projected_map", latched());
  stats_pub_ = create_publisher<std_msgs::msg::String>("~/stats", latched());
  path_check_pub_ = create_publisher<std_msgs::msg::String>("~/path_check", latched());
  path_markers_pub_ = create_publisher<visualization_msgs::msg::MarkerArray>("~/path_check_markers", latched());

  live::RebuildWorker::Hooks hooks;
  hooks.publish_map = [this](const live::MapPublication& p) { publishMap(p); };
  hooks.publish_stats = [this](const std::string& json) {
    std_msgs::msg::String msg;
    msg.data = json;
    stats_pub_->publish(msg);
  };
  hooks.rebuild_failed = [this](const std::string& why) { RCLCPP_ERROR(get_logger(), "hullmap: %s", why.c_str()); };
  worker_ = std::make_unique<live::RebuildWorker>(settings, std::move(hooks), "~/keyframes");

  subscribeMapInputs();
  path_sub_ = create_subscription<nav_msgs::msg::Path>("~/check_path", input(10),
                                                       [this](const nav_msgs::msg::Path& m) { onPath(m); });
  save_srv_ = create_service<std_srvs::srv::Trigger>(
      "~/save", [this](const std::shared_ptr<std_srvs::srv::Trigger::Request>,
                       std::shared_ptr<std_srvs::srv::Trigger::Response> response) {
        const live::SaveAnswer answer = worker_->save();
        response->success = answer.success;
        response->message = answer.message;
      });
  reset_srv_ = create_service<std_srvs::srv::Empty>(
      "~/reset",
      [this](const std::shared_ptr<std_srvs::srv::Empty::Request>, std::shared_ptr<std_srvs::srv::Empty::Response>) {
        orbslam_.clear();
        keyframes_.reset();
        worker_->reset();
      });
  check_path_srv_ = create_service<hullmap_interfaces::srv::CheckPath>(
      "~/check_path", [this](const std::shared_ptr<hullmap_interfaces::srv::CheckPath::Request> request,
                             std::shared_ptr<hullmap_interfaces::srv::CheckPath::Response> response) {
        onCheckPath(*request, *response);
      });
  parameters_callback_ = add_on_set_parameters_callback(
      [this](const std::vector<rclcpp::Parameter>& parameters) { return onSetParameters(parameters); });
}

HullmapNode::~HullmapNode() {
  // No callback may reach the worker while it stops: subscriptions and services go first.
  parameters_callback_.reset();
  follow_timer_.reset();
  marker_input_.reset();
  cloud_input_.reset();
  keyframes_input_.reset();
  path_sub_.reset();
  save_srv_.reset();
  reset_srv_.reset();
  check_path_srv_.reset();
  worker_.reset();
}

void HullmapNode::subscribeMapInputs() {
  const auto lost = [this](const std::string& topic, std::size_t count, const InputQos& qos) {
    onLost(topic, count, qos);
  };
  const auto changed = [this](const std::string& topic, std::size_t publishers, const InputQos& qos) {
    RCLCPP_INFO(get_logger(), "hullmap: %s: %s, as its %zu publisher%s", topic.c_str(), describe(qos).c_str(),
                publishers, publishers == 1 ? "" : "s");
    worker_->setInput(topic, describe(qos));
  };
  // Depth 2 for the maps: each re-sends the whole map, so an older message is never needed; 20 for
  // ORB-SLAM's markers, which interleave keyframe and graph markers with the map's.
  marker_input_ = std::make_unique<MapInput<visualization_msgs::msg::Marker>>(
      *this, "/ORB_SLAM/Map", 20, [this](const visualization_msgs::msg::Marker& m) { onMarker(m); }, lost, changed);
  cloud_input_ = std::make_unique<MapInput<sensor_msgs::msg::PointCloud2>>(
      *this, "~/cloud_in", 2, [this](const sensor_msgs::msg::PointCloud2& m) { onCloud(m); }, lost, changed);
  keyframes_input_ = std::make_unique<MapInput<nav_msgs::msg::Path>>(
      *this, "~/keyframes", 2, [this](const nav_msgs::msg::Path& m) { onKeyframes(m); }, lost, changed);
  worker_->setInput(marker_input_->topic(), describe(marker_input_->qos()));
  worker_->setInput(cloud_input_->topic(), describe(cloud_input_->qos()));
  worker_->setInput(keyframes_input_->topic(), describe(keyframes_input_->qos()));
  follow_timer_ = create_wall_timer(kFollowPeriod, [this] {
    tellBestEffort(marker_input_->topic(), marker_input_->follow());
    tellBestEffort(cloud_input_->topic(), cloud_input_->follow());
    tellBestEffort(keyframes_input_->topic(), keyframes_input_->follow());
  });
}

void HullmapNode::tellBestEffort(const std::string& topic, std::size_t publishers) {
  if (publishers == 0 || !best_effort_told_.insert(topic).second) return;
  RCLCPP_WARN(get_logger(),
              "hullmap: %s has a best-effort publisher: a map of more than about 1 MB (100,000 points) may be lost "
              "whole in transport, and the middleware may not say so; publish big maps reliably (the node "
              "follows), or give the node a socket receive buffer that holds them (docs/ROS.md, Big maps)",
              topic.c_str());
}

void HullmapNode::onLost(const std::string& topic, std::size_t count, const InputQos& qos) {
  // A reliable link loses nothing in transport: what it misses was replaced in a full queue.
  const std::string why = std::to_string(count) + " message" + (count == 1 ? "" : "s") + " on " + topic +
                          (qos.reliable ? " replaced in the subscription's queue (" : " lost in transport (") +
                          describe(qos) + ")";
  worker_->lost(count, why);
  if (lost_told_.insert(topic).second) {
    RCLCPP_WARN(get_logger(),
                "hullmap: %s; a best-effort link loses a message of many fragments whole when one fragment is "
                "lost: publish big maps reliably (the node follows its publishers), or give the node "
                "qos_overrides.%s.subscription.reliability:=reliable, and a socket receive buffer that holds the "
                "map (docs/ROS.md, Big maps)",
                why.c_str(), topic.c_str());
  } else {
    RCLCPP_DEBUG(get_logger(), "hullmap: %s", why.c_str());
  }
}

void HullmapNode::declareParameters() {
  for (const auto& spec : live::nodeParameters()) {
    try {
      declare_parameter(spec.name, toRclcppValue(spec.default_value), descriptor(spec));
    } catch (const rclcpp::exceptions::InvalidParameterValueException& e) {
      // rclcpp refused the value given at start (out of the descriptor's range): say why as the
      // node would when it is set later.
      const auto& overrides = get_node_parameters_interface()->get_parameter_overrides();
      const auto given = overrides.find(spec.name);
      live::ParameterValue value;
      if (given != overrides.end() && toParameterValue(given->second, value)) {
        live::readSettings({{spec.name, value}}, live::Checking::kStrict);
      }
      throw Error::inParameter(spec.name, e.what());
    } catch (const rclcpp::exceptions::InvalidParameterTypeException& e) {
      throw Error::inParameter(spec.name, e.what());
    }
    live::ParameterValue value;
    if (toParameterValue(get_parameter(spec.name).get_parameter_value(), value)) values_[spec.name] = value;
  }
}

rcl_interfaces::msg::SetParametersResult HullmapNode::onSetParameters(
    const std::vector<rclcpp::Parameter>& parameters) {
  rcl_interfaces::msg::SetParametersResult result;
  result.successful = true;
  live::ParameterValues values = values_;
  bool ours = false;
  for (const auto& p : parameters) {
    if (!live::findParameter(p.get_name())) continue;  // use_sim_time, qos_overrides.*: rclcpp's
    ours = true;
    live::ParameterValue value;
    if (toParameterValue(p.get_parameter_value(), value)) {
      values[p.get_name()] = value;
    } else {
      values.erase(p.get_name());
    }
  }
  if (!ours) return result;
  try {
    live::NodeSettings settings = live::readSettings(values, live::Checking::kStrict);
    // Where the octree reaches: a resolution or scale that would leave no point of the map inside it.
    std::string reach;
    for (const auto& p : parameters) {
      if (p.get_name() == "resolution" || p.get_name() == "scale") reach += (reach.empty() ? "" : "/") + p.get_name();
    }
    const std::string unbuildable = reach.empty() ? std::string() : worker_->unbuildable(settings);
    if (!unbuildable.empty()) throw Error::inParameter(reach, unbuildable);
    values_ = std::move(values);
    worker_->setSettings(std::move(settings));
  } catch (const Error& e) {
    result.successful = false;
    result.reason = e.what();
  }
  return result;
}

void HullmapNode::skip(const std::string& why) {
  RCLCPP_WARN(get_logger(), "hullmap: message skipped: %s", why.c_str());
  worker_->skip(why);
}

void HullmapNode::onMarker(const visualization_msgs::msg::Marker& msg) {
  try {
    if (!orbslam_.add(markerKey(msg), msg.points)) return;
  } catch (const Error& e) {
    skip(std::string("/ORB_SLAM/Map: ") + e.what());
    return;
  }
  worker_->submit({orbslam_.points(), toNanoseconds(msg.header.stamp), live::Clock::now(), keyframes_, true});
}

void HullmapNode::onCloud(const sensor_msgs::msg::PointCloud2& msg) {
  const auto received = live::Clock::now();
  try {
    std::size_t non_finite = 0;
    io::Points points = cloudPoints(msg, &non_finite);
    if (non_finite > 0) {
      RCLCPP_DEBUG(get_logger(), "~/cloud_in: %zu points with a non-finite coordinate skipped", non_finite);
    }
    worker_->submit({std::move(points), toNanoseconds(msg.header.stamp), received, keyframes_, std::nullopt});
  } catch (const Error& e) {
    skip(std::string("~/cloud_in: ") + e.what());
  }
}

void HullmapNode::onKeyframes(const nav_msgs::msg::Path& msg) {
  auto poses = std::make_shared<std::vector<io::Keyframe>>(keyframes(msg));
  if (!live::normaliseKeyframes(*poses)) {
    skip("~/keyframes: a pose is not finite or its quaternion is zero");
    return;
  }
  if (poses->empty()) poses.reset();
  keyframes_ = std::move(poses);
}

std::vector<Eigen::Vector3d> HullmapNode::waypoints(const nav_msgs::msg::Path& path) {
  if (!path.header.frame_id.empty() && path.header.frame_id != frame_id_) {
    RCLCPP_WARN(get_logger(), "hullmap: ~/check_path: path in frame %s, checked as if in %s (no tf lookup)",
                path.header.frame_id.c_str(), frame_id_.c_str());
  }
  std::vector<Eigen::Vector3d> points;
  for (const auto& p : path.poses) points.emplace_back(p.pose.position.x, p.pose.position.y, p.pose.position.z);
  return points;
}

void HullmapNode::onPath(const nav_msgs::msg::Path& msg) {
  if (msg.poses.empty()) {
    RCLCPP_WARN(get_logger(), "hullmap: ~/check_path: a path without poses, skipped");
    return;
  }
  live::PathCheckAnswer answer;
  try {
    answer = worker_->checkPath(waypoints(msg));
  } catch (const Error& e) {
    RCLCPP_WARN(get_logger(), "hullmap: ~/check_path: %s; skipped", e.what());
    return;
  }
  std_msgs::msg::String lines;
  lines.data = answer.json_lines;
  path_check_pub_->publish(lines);
  path_markers_pub_->publish(toMarkerArray(answer.markers, header(toNanoseconds(msg.header.stamp))));
}

void HullmapNode::onCheckPath(const hullmap_interfaces::srv::CheckPath::Request& request,
                              hullmap_interfaces::srv::CheckPath::Response& response) {
  response.first_colliding_segment = -1;
  if (request.path.poses.empty()) {
    response.success = false;
    response.message = "a path without poses";
    return;
  }
  const std::vector<Eigen::Vector3d> points = waypoints(request.path);
  live::PathCheckAnswer answer;
  try {
    answer = worker_->checkPath(points, request.radius);
  } catch (const Error& e) {
    response.success = false;
    response.message = e.what();
    return;
  }
  response.success = true;
  for (std::size_t i = 0; i < answer.check.segments.size(); ++i) {
    const collision::SegmentCheck& c = answer.check.segments[i];
    const Eigen::Vector3d& a = points[i];
    const Eigen::Vector3d& b = points.size() > i + 1 ? points[i + 1] : points[i];
    hullmap_interfaces::msg::SegmentCheck s;
    s.collides = c.collides;
    s.t = c.t;
    const Eigen::Vector3d contact = a + c.t * (b - a);
    s.contact.x = contact.x();
    s.contact.y = contact.y();
    s.contact.z = contact.z();
    s.obstacle = c.obstacle;
    s.part = c.part;
    s.surface = c.surface;
    s.clearance = c.clearance;
    response.segments.push_back(s);
  }
  if (answer.check.first_colliding_segment) {
    response.first_colliding_segment = static_cast<std::int32_t>(*answer.check.first_colliding_segment);
    if (answer.check.first_contact) {
      response.first_contact.x = answer.check.first_contact->x();
      response.first_contact.y = answer.check.first_contact->y();
      response.first_contact.z = answer.check.first_contact->z();
    }
  }
  path_markers_pub_->publish(toMarkerArray(answer.markers, header(toNanoseconds(request.path.header.stamp))));
}

std_msgs::msg::Header HullmapNode::header(std::int64_t stamp_ns) {
  std_msgs::msg::Header h;
  h.frame_id = frame_id_;
  h.stamp = stamp_ns == 0 ? static_cast<builtin_interfaces::msg::Time>(now()) : toStamp(stamp_ns);
  return h;
}

void HullmapNode::publishMap(const live::MapPublication& p) {
  const std_msgs::msg::Header h = header(p.stamp_ns);
  obstacles_pub_->publish(toMarkerArray(p.obstacles, h));
  cells_pub_->publish(toMarkerArray(p.occupied_cells, h));
  grid_pub_->publish(toOccupancyGrid(p.projected_map, h));
}

}  // namespace hullmap::ros2

RCLCPP_COMPONENTS_REGISTER_NODE(hullmap::ros2::HullmapNode)
