// Channels of catalogue topics in an MCAP file, laid out as every scanbus writer (recorder,
// `sim mav`, `scanmatch convert`) lays them out: the ROS topic name (/scan), `cdr`
// messages, the type's ros2msg schema (written once per type) and rosbag2's
// `offered_qos_profiles` metadata from the catalogue QoS.
#pragma once

#include <map>
#include <string>

#include "scanbus/recorder/mcap_writer.hpp"
#include "scanbus/topics.hpp"

namespace scanbus::recorder {

class TopicChannels {
 public:
  explicit TopicChannels(McapWriter& writer) : writer_(writer) {}
  // The new channel's id; `topic` is a DDS name in the catalogue.
  uint16_t add(const std::string& topic);

 private:
  McapWriter& writer_;
  std::map<std::string, uint16_t> schema_of_type_;
};

}  // namespace scanbus::recorder
