#include "scanbus/sensor/laser_scan.hpp"

#include <Eigen/Geometry>

#include <algorithm>

namespace scanbus::sensor {

std::vector<Eigen::Vector2d> kept_points(const LaserScan& scan, const RangeGate& gate) {
  const double low = std::max(scan.range_min, gate.range_min);
  const double high = std::min(scan.range_max, gate.range_max);
  const double middle = scan.middle_angle(), half_opening = gate.opening / 2 + 1e-9;
  // Each ray's direction is the previous one turned by the increment: one sincos per scan
  // instead of one per ray (a tenth of the scan matcher's time); the rounding error after a
  // few thousand turns stays below 1e-12.
  const Eigen::Matrix2d turn = Eigen::Rotation2Dd(scan.angle_increment).toRotationMatrix();
  Eigen::Vector2d direction(std::cos(scan.angle_min), std::sin(scan.angle_min));
  std::vector<Eigen::Vector2d> points;
  points.reserve(scan.ranges.size());
  for (size_t i = 0; i < scan.ranges.size(); ++i, direction = turn * direction) {
    const double range = scan.ranges[i];
    // NaN fails every comparison; inf fails the upper limit.
    if (!(range > 0 && range >= low && range <= high)) continue;
    if (std::abs(scan.angle(i) - middle) > half_opening) continue;
    points.push_back(range * direction);
  }
  return points;
}

}  // namespace scanbus::sensor
