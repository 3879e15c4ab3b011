#include <gtest/gtest.h>

#include <limits>

#include "scanbus/laser_scan_message.hpp"

// A scan reaches a subscriber whole: stamp, geometry, its own range limits, every range (no
// return included), and the angle_max ROS tools read.
TEST(LaserScanMessage, TheScanSurvivesTheMessage) {
  scanbus::sensor::LaserScan scan;
  scan.stamp = 1700000000.25;
  scan.angle_min = -M_PI / 4;
  scan.angle_increment = M_PI / 360;
  scan.range_min = 0.05;
  scan.range_max = 30;
  scan.ranges = {1.5f, std::numeric_limits<float>::infinity(), 2.25f};
  const auto message = scanbus::to_laser_scan_message(scan, "laser");
  EXPECT_EQ(message.header().frame_id(), "laser");
  EXPECT_NEAR(message.angle_max(), -M_PI / 4 + 2 * M_PI / 360, 1e-6);
  const auto back = scanbus::from_laser_scan_message(message);
  EXPECT_NEAR(back.stamp, scan.stamp, 1e-6);
  EXPECT_NEAR(back.angle_min, scan.angle_min, 1e-6);
  EXPECT_NEAR(back.angle_increment, scan.angle_increment, 1e-6);
  EXPECT_NEAR(back.range_min, 0.05, 1e-6);
  EXPECT_NEAR(back.range_max, 30, 1e-6);
  EXPECT_EQ(back.ranges, scan.ranges);
  EXPECT_EQ(scanbus::to_laser_scan_message({}, "laser").angle_max(), 0.0f);  // no rays
}
