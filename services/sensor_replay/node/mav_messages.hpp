// A MAV log's records as the sensors' ROS 2 messages, and a MAV log as an MCAP recording of
// those messages (the format `scanbus sim mav --out F.mcap` writes and `scanbus replay`
// publishes): rt/scan, rt/imu, rt/fix, rt/pressure and rt/truth/pose, log times the
// records' stamps, the META lines in a Metadata record named "scanbus_mav_log".
#pragma once

#include <string>

#include "scanbus/sensor_replay/mav_log.hpp"
#include "scanbus_msgs/FluidPressure.h"
#include "scanbus_msgs/Imu.h"
#include "scanbus_msgs/NavSatFix.h"
#include "scanbus_msgs/PoseStamped.h"

namespace scanbus::sensor_replay {

struct MavFrames {
  std::string laser = "laser", base_link = "base_link", gps = "gps", map = "map";
};

sensor_msgs::msg::Imu imu_message(const ImuRecord& record, const std::string& frame);
sensor_msgs::msg::NavSatFix fix_message(const GpsRecord& record, const std::string& frame);
sensor_msgs::msg::FluidPressure pressure_message(const BaroRecord& record, const std::string& frame);
geometry_msgs::msg::PoseStamped truth_message(const TruthRecord& record, const std::string& frame);

void write_mav_mcap(const std::string& path, const MavLog& log, const MavFrames& frames = {});
// Throws MavLogError naming the file and what is missing or malformed (MCAP damage too).
MavLog read_mav_mcap(const std::string& path);
// By extension: .mcap as above, anything else as the text log (docs/mav_log.md).
MavLog load_mav_log(const std::string& path);
void save_mav_log(const std::string& path, const MavLog& log);

}  // namespace scanbus::sensor_replay
