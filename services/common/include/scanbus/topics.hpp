// The topic catalogue: every topic scanbus uses, its ROS 2 type name, default QoS and who
// writes and reads it. docs/topics.md is checked against this table by a test.
#pragma once

#include <string>
#include <vector>

#include "scanbus/config.hpp"

namespace scanbus {

struct QosSettings {
  bool reliable = true;
  bool transient_local = false;
  bool keep_all = false;
  int depth = 10;
};

struct TopicInfo {
  std::string name;  // DDS topic name, with the ROS 2 "rt/" prefix
  std::string type;  // registered DDS type name, ROS 2 style
  QosSettings qos;
  std::string publishers;
  std::string subscribers;
  std::string description;
};

const std::vector<TopicInfo>& topic_catalogue();
// nullptr when the name is not in the catalogue.
const TopicInfo* find_topic(const std::string& name);
// The catalogue entry; throws std::invalid_argument naming the topic when it is not there.
const TopicInfo& topic_info(const std::string& name);

// Default QoS of a topic overridden by the `qos.<topic>` section of a config, if any:
//   qos:
//     rt/scanner/cloud: {reliability: reliable, durability: transient_local, history: keep_last, depth: 1}
QosSettings qos_from_config(const Config& qos_section, const TopicInfo& topic);
std::string describe(const QosSettings& qos);

}  // namespace scanbus
