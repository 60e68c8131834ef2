#include "hullmap/ros2/map_input.hpp"

#include <cstdint>
#include <string>

namespace hullmap::ros2 {

InputQos matchPublishers(const std::vector<rclcpp::TopicEndpointInfo>& publishers) {
  InputQos qos;
  if (publishers.empty()) return qos;
  qos.reliable = qos.transient_local = true;
  for (const auto& p : publishers) {
    const rclcpp::QoS& offered = p.qos_profile();
    qos.reliable = qos.reliable && offered.reliability() == rclcpp::ReliabilityPolicy::Reliable;
    qos.transient_local = qos.transient_local && offered.durability() == rclcpp::DurabilityPolicy::TransientLocal;
  }
  return qos;
}

std::size_t missedBefore(live::SequenceGaps& gaps, const rmw_message_info_t& info) {
  const std::uint64_t sequence = info.publication_sequence_number;
  if (sequence == RMW_MESSAGE_INFO_SEQUENCE_NUMBER_UNSUPPORTED) return 0;
  const auto* gid = reinterpret_cast<const char*>(info.publisher_gid.data);
  return static_cast<std::size_t>(gaps.missed(std::string(gid, RMW_GID_STORAGE_SIZE), sequence));
}

std::string describe(const InputQos& qos) {
  return std::string(qos.reliable ? "reliable" : "best effort") + ", " +
         (qos.transient_local ? "transient_local" : "volatile");
}

}  // namespace hullmap::ros2
