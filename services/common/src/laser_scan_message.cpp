#include "scanbus/laser_scan_message.hpp"

#include "scanbus/clock.hpp"

namespace scanbus {

sensor_msgs::msg::LaserScan to_laser_scan_message(const sensor::LaserScan& scan, const std::string& frame_id) {
  sensor_msgs::msg::LaserScan message;
  message.header().stamp(to_stamp(scan.stamp));
  message.header().frame_id(frame_id);
  message.angle_min(static_cast<float>(scan.angle_min));
  message.angle_increment(static_cast<float>(scan.angle_increment));
  message.angle_max(static_cast<float>(scan.ranges.empty() ? scan.angle_min : scan.angle(scan.ranges.size() - 1)));
  message.range_min(static_cast<float>(scan.range_min));
  message.range_max(static_cast<float>(scan.range_max));
  message.ranges(scan.ranges);
  return message;
}

sensor::LaserScan from_laser_scan_message(const sensor_msgs::msg::LaserScan& message) {
  sensor::LaserScan scan;
  scan.stamp = to_seconds(message.header().stamp());
  scan.angle_min = message.angle_min();
  scan.angle_increment = message.angle_increment();
  scan.range_min = message.range_min();
  scan.range_max = message.range_max();
  scan.ranges = message.ranges();
  return scan;
}

}  // namespace scanbus
