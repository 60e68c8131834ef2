// hullmap_node: HullmapNode on its own (the component loads into a container as well).
#include <memory>

#include <rclcpp/rclcpp.hpp>

#include "hullmap/core/error.hpp"
#include "hullmap/ros2/hullmap_node.hpp"

int main(int argc, char** argv) {
  rclcpp::init(argc, argv);
  int status = 0;
  try {
    auto node = std::make_shared<hullmap::ros2::HullmapNode>();
    rclcpp::spin(node);
  } catch (const hullmap::Error& e) {
    // A bad parameter at start: one line naming it, exit 2.
    RCLCPP_FATAL(rclcpp::get_logger("hullmap"), "hullmap: %s", e.what());
    status = 2;
  }
  rclcpp::shutdown();
  return status;
}
