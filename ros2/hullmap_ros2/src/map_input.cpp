#include "hullmap/ros2/map_input.hpp"

#include <algorithm>
#include <iterator>

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

std::size_t SequenceGaps::missed(const rmw_message_info_t& info) {
  const std::uint64_t sequence = info.publication_sequence_number;
  if (sequence == RMW_MESSAGE_INFO_SEQUENCE_NUMBER_UNSUPPORTED || sequence == 0) return 0;
  std::array<std::uint8_t, RMW_GID_STORAGE_SIZE> gid{};
  std::copy(std::begin(info.publisher_gid.data), std::end(info.publisher_gid.data), gid.begin());
  auto [it, first] = last_.emplace(gid, sequence);
  if (first) return 0;
  const std::uint64_t last = it->second;
  it->second = sequence;
  return sequence > last + 1 ? std::size_t(sequence - last - 1) : 0;
}

std::string describe(const InputQos& qos) {
  return std::string(qos.reliable ? "reliable" : "best effort") + ", " +
         (qos.transient_local ? "transient_local" : "volatile");
}

}  // namespace hullmap::ros2
