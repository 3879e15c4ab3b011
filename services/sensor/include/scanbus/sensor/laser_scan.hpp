// One planar laser scan and the one rule for which of its rays a consumer keeps: the scan
// matcher, the cloud builders, the log readers and the simulator share them.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <vector>

namespace scanbus::sensor {

// sensor_msgs/LaserScan's geometry. A ray with no return holds NaN, inf, zero or a range
// outside the scan's own range_min..range_max (limits that are not numbers keep no ray).
struct LaserScan {
  double stamp = 0;                                                           // s
  double angle_min = 0, angle_increment = 0;                                  // rad
  double range_min = 0, range_max = std::numeric_limits<double>::infinity();  // m (inf: no limit given)
  std::vector<float> ranges;                                                  // m

  double angle(size_t ray) const { return angle_min + angle_increment * static_cast<double>(ray); }
  double middle_angle() const { return angle_min + angle_increment * (static_cast<double>(ranges.size()) - 1) / 2; }
};

// What a consumer keeps of a scan, besides the scan's own limits.
struct RangeGate {
  double range_min = 0;       // m
  double range_max = 30.0;    // m (the MAV paper keeps ranges up to 30 m)
  double opening = 2 * M_PI;  // rad kept around the middle ray (the paper: 90 degrees)
};

// The kept returns in the laser frame (x along angle 0), in ray order.
std::vector<Eigen::Vector2d> kept_points(const LaserScan& scan, const RangeGate& gate);

}  // namespace scanbus::sensor
