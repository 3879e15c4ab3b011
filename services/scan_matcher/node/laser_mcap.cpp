#include "laser_mcap.hpp"

#include <cmath>

#include "cdr.hpp"
#include "scanbus/laser_scan_message.hpp"
#include "scanbus/recorder/mcap_reader.hpp"
#include "scanbus/recorder/mcap_writer.hpp"
#include "scanbus/recorder/ros2msg.hpp"
#include "scanbus/typed_topics.hpp"
#include "scanbus_msgs/LaserScanPubSubTypes.h"
#include "topic_channels.hpp"

namespace scanbus::scan_matcher {

void write_laser_mcap(const std::string& path, const std::vector<LaserRecord>& records, const std::string& frame) {
  using namespace recorder;
  McapWriter writer(path, {});
  const uint16_t channel = TopicChannels(writer).add(topics::kScan.name);
  uint32_t sequence = 0;
  for (const auto& record : records) {
    const auto bytes = to_cdr<sensor_msgs::msg::LaserScanPubSubType>(to_laser_scan_message(record.scan, frame));
    const auto time = static_cast<uint64_t>(std::llround(record.scan.stamp * 1e9));
    writer.write(channel, sequence++, time, time, bytes.data(), bytes.size());
  }
  writer.close();
}

std::vector<LaserRecord> read_laser_mcap(const std::string& path) {
  using namespace recorder;
  std::vector<LaserRecord> records;
  try {
    McapReader(path).read_messages([&](const McapMessage& m, const McapChannel& channel) {
      if (dds_topic_of_ros_topic(channel.topic) != topics::kScan.name) return;
      LaserRecord record;
      record.scan = from_laser_scan_message(from_cdr<sensor_msgs::msg::LaserScanPubSubType>(m.data, m.size));
      records.push_back(std::move(record));
    });
  } catch (const std::runtime_error& error) {  // McapError, undecodable bytes
    throw LogError(error.what());
  }
  if (records.empty()) throw LogError(path + ": no LaserScan messages on /scan");
  return records;
}

std::vector<LaserRecord> load_laser_log(const std::string& path) {
  return recorder::is_mcap_path(path) ? read_laser_mcap(path) : read_carmen_log(path);
}

}  // namespace scanbus::scan_matcher
