#include "laser_mcap.hpp"

#include <cmath>

#include "LaserScanPubSubTypes.h"
#include "cdr.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/recorder/mcap_reader.hpp"
#include "scanbus/recorder/mcap_writer.hpp"
#include "scanbus/recorder/ros2msg.hpp"
#include "scanbus/typed_topics.hpp"
#include "topic_channels.hpp"

namespace scanbus::scan_matcher {

void write_laser_mcap(const std::string& path, const std::vector<LaserRecord>& records, const std::string& frame) {
  using namespace recorder;
  McapWriter writer(path, {});
  const uint16_t channel = TopicChannels(writer).add(topics::kScan.name);
  uint32_t sequence = 0;
  for (const auto& record : records) {
    sensor_msgs::msg::LaserScan scan;
    scan.header().stamp(to_stamp(record.stamp));
    scan.header().frame_id(frame);
    scan.angle_min(static_cast<float>(record.angle_min));
    scan.angle_increment(static_cast<float>(record.angle_increment));
    scan.angle_max(static_cast<float>(
        record.angle_min + record.angle_increment * (record.ranges.empty() ? 0.0 : record.ranges.size() - 1.0)));
    scan.range_max(static_cast<float>(record.range_max));
    scan.ranges(record.ranges);
    const auto bytes = to_cdr<sensor_msgs::msg::LaserScanPubSubType>(scan);
    const auto time = static_cast<uint64_t>(std::llround(record.stamp * 1e9));
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
      const auto scan = from_cdr<sensor_msgs::msg::LaserScanPubSubType>(m.data, m.size);
      LaserRecord record;
      record.stamp = to_seconds(scan.header().stamp());
      record.angle_min = scan.angle_min();
      record.angle_increment = scan.angle_increment();
      record.range_max = scan.range_max();
      record.ranges = scan.ranges();
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
