#include "topic_channels.hpp"

#include "scanbus/recorder/ros2msg.hpp"

namespace scanbus::recorder {

namespace {

// rosbag2's `offered_qos_profiles` channel metadata for a QoS.
std::string offered_qos_profiles(const QosSettings& qos) {
  // rmw's enums: history 1 keep last / 2 keep all, reliability 1 reliable / 2 best effort,
  // durability 1 transient local / 2 volatile; zero durations mean "default".
  const std::string zero = "\n    sec: 0\n    nsec: 0";
  return "- history: " + std::to_string(qos.keep_all ? 2 : 1) + "\n  depth: " + std::to_string(qos.depth) +
         "\n  reliability: " + std::to_string(qos.reliable ? 1 : 2) +
         "\n  durability: " + std::to_string(qos.transient_local ? 1 : 2) + "\n  deadline:" + zero +
         "\n  lifespan:" + zero + "\n  liveliness: 1\n  liveliness_lease_duration:" + zero +
         "\n  avoid_ros_namespace_conventions: false\n";
}

}  // namespace

uint16_t TopicChannels::add(const std::string& topic) {
  const TopicInfo& info = topic_info(topic);
  const std::string ros_type = ros_type_of_dds_type(info.type);
  auto schema = schema_of_type_.find(ros_type);
  if (schema == schema_of_type_.end())
    schema =
        schema_of_type_
            .emplace(ros_type, writer_.add_schema(ros_type, "ros2msg", Ros2MsgCatalogue::scanbus().schema(ros_type)))
            .first;
  return writer_.add_channel(schema->second, ros_topic_of_dds_topic(topic), "cdr",
                             {{"offered_qos_profiles", offered_qos_profiles(info.qos)}});
}

}  // namespace scanbus::recorder
