// Planar poses (x, y in m, theta in rad) and their composition.
#pragma once

#include <cmath>

namespace scanbus::scan_matcher {

struct Pose2 {
  double x = 0, y = 0, theta = 0;

  // this * other: other expressed in this pose's frame, brought to the outer frame.
  Pose2 operator*(const Pose2& other) const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {x + c * other.x - s * other.y, y + s * other.x + c * other.y, normalize(theta + other.theta)};
  }
  Pose2 inverse() const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {-(c * x + s * y), -(-s * x + c * y), normalize(-theta)};
  }
  double distance() const { return std::hypot(x, y); }

  static double normalize(double angle) { return std::remainder(angle, 2 * M_PI); }
};

}  // namespace scanbus::scan_matcher
