#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <rclcpp/rclcpp.hpp>

#include "hullmap/live/map_messages.hpp"

namespace hullmap::ros2 {

/// The reliability and durability a map input asks for.
struct InputQos {
  bool reliable = false;         ///< false: best effort
  bool transient_local = false;  ///< false: volatile
  bool operator==(const InputQos& o) const { return reliable == o.reliable && transient_local == o.transient_local; }
};

/// What matches every one of `publishers` (rosbag2's rule): reliable when all offer reliable,
/// transient_local when all offer it; best effort and volatile when there are none, which match
/// any publisher that comes.
InputQos matchPublishers(const std::vector<rclcpp::TopicEndpointInfo>& publishers);

/// "reliable, volatile": a QoS in words, for the log.
std::string describe(const InputQos& qos);

/// Messages of `info`'s publisher that `gaps` says were missed before this one (0 where the
/// middleware gives no sequence numbers, as CycloneDDS under Humble).
std::size_t missedBefore(live::SequenceGaps& gaps, const rmw_message_info_t& info);

/// A map input (`/ORB_SLAM/Map`, `~/cloud_in`, `~/keyframes`) whose subscription follows the QoS of
/// the publishers on its topic: follow() re-creates it when they ask for another reliability or
/// durability (a reliable publisher's big map then arrives whole, retransmitted). A reliability or
/// durability the user gave through the QoS overrides is kept, never followed. Messages missed (rclcpp's
/// message-lost event; the gaps in a publisher's sequence numbers) go to `on_lost`. Use from the
/// node's executor only.
template <typename Message>
class MapInput {
 public:
  using OnMessage = std::function<void(const Message&)>;
  /// `count`: messages lost since the last call; `qos`: the subscription's at the time.
  using OnLost = std::function<void(const std::string& topic, std::size_t count, const InputQos& qos)>;
  using OnChange = std::function<void(const std::string& topic, std::size_t publishers, const InputQos& qos)>;

  /// Subscribes to `topic` (keep last `depth`, best effort and volatile unless overridden).
  MapInput(rclcpp::Node& node, const std::string& topic, std::size_t depth, OnMessage on_message, OnLost on_lost,
           OnChange on_change)
      : node_(node),
        on_message_(std::move(on_message)),
        on_lost_(std::move(on_lost)),
        on_change_(std::move(on_change)),
        name_(topic) {
    rclcpp::SubscriptionOptions options = optionsWithEvents();
    options.qos_overriding_options = rclcpp::QosOverridingOptions::with_default_policies();
    subscribe(rclcpp::QoS(depth).best_effort().durability_volatile(), options);
    topic_ = subscription_->get_topic_name();
    const auto& overrides = node_.get_node_parameters_interface()->get_parameter_overrides();
    const std::string prefix = "qos_overrides." + topic_ + ".subscription.";
    fixed_reliability_ = overrides.count(prefix + "reliability") > 0;
    fixed_durability_ = overrides.count(prefix + "durability") > 0;
    qos_ = actual();
  }

  MapInput(const MapInput&) = delete;
  MapInput& operator=(const MapInput&) = delete;

  /// Re-creates the subscription when the publishers on the topic ask for another QoS. Returns how
  /// many of them are best effort.
  std::size_t follow() {
    const auto publishers = node_.get_publishers_info_by_topic(topic_);
    std::size_t best_effort = 0;
    for (const auto& p : publishers)
      best_effort += p.qos_profile().reliability() == rclcpp::ReliabilityPolicy::BestEffort;
    InputQos wanted = matchPublishers(publishers);
    if (fixed_reliability_) wanted.reliable = qos_.reliable;
    if (fixed_durability_) wanted.transient_local = qos_.transient_local;
    if (wanted == qos_) return best_effort;
    rclcpp::QoS qos = subscription_->get_actual_qos();
    qos.reliability(wanted.reliable ? rclcpp::ReliabilityPolicy::Reliable : rclcpp::ReliabilityPolicy::BestEffort);
    qos.durability(wanted.transient_local ? rclcpp::DurabilityPolicy::TransientLocal
                                          : rclcpp::DurabilityPolicy::Volatile);
    subscription_.reset();
    subscribe(qos, optionsWithEvents());
    qos_ = actual();
    if (on_change_) on_change_(topic_, publishers.size(), qos_);
    return best_effort;
  }

  const std::string& topic() const { return topic_; }
  const InputQos& qos() const { return qos_; }

 private:
  rclcpp::SubscriptionOptions optionsWithEvents() {
    rclcpp::SubscriptionOptions options;
    options.event_callbacks.message_lost_callback = [this](rclcpp::QOSMessageLostInfo& info) {
      if (on_lost_ && info.total_count_change > 0) on_lost_(topic_, info.total_count_change, qos_);
    };
    return options;
  }

  void subscribe(const rclcpp::QoS& qos, rclcpp::SubscriptionOptions options) {
    auto callback = [this](const Message& m, const rclcpp::MessageInfo& info) {
      const std::size_t missed = missedBefore(gaps_, info.get_rmw_message_info());
      if (missed > 0 && on_lost_) on_lost_(topic_, missed, qos_);
      on_message_(m);
    };
    gaps_.clear();
    try {
      subscription_ = node_.create_subscription<Message>(topic_.empty() ? name_ : topic_, qos, callback, options);
    } catch (const rclcpp::UnsupportedEventTypeException&) {
      // A middleware without the message-lost event: the subscription without it.
      options.event_callbacks.message_lost_callback = nullptr;
      subscription_ = node_.create_subscription<Message>(topic_.empty() ? name_ : topic_, qos, callback, options);
    }
  }

  InputQos actual() const {
    const rclcpp::QoS qos = subscription_->get_actual_qos();
    return {qos.reliability() == rclcpp::ReliabilityPolicy::Reliable,
            qos.durability() == rclcpp::DurabilityPolicy::TransientLocal};
  }

  rclcpp::Node& node_;
  OnMessage on_message_;
  OnLost on_lost_;
  OnChange on_change_;
  std::string name_;   // as given ("~/cloud_in")
  std::string topic_;  // resolved ("/hullmap/cloud_in")
  bool fixed_reliability_ = false, fixed_durability_ = false;
  live::SequenceGaps gaps_;
  InputQos qos_;
  typename rclcpp::Subscription<Message>::SharedPtr subscription_;
};

}  // namespace hullmap::ros2
