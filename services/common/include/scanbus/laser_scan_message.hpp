// sensor::LaserScan to and from sensor_msgs/LaserScan: the nodes, the replay and the laser
// MCAP files convert here, and nowhere else.
#pragma once

#include <string>

#include "scanbus/sensor/laser_scan.hpp"
#include "scanbus_msgs/LaserScanPubSubTypes.h"

namespace scanbus {

sensor_msgs::msg::LaserScan to_laser_scan_message(const sensor::LaserScan& scan, const std::string& frame_id);
sensor::LaserScan from_laser_scan_message(const sensor_msgs::msg::LaserScan& message);

}  // namespace scanbus
