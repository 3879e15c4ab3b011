// An initial guess from the IMU: how far the body turned about the laser's z axis (the
// axis its scan plane turns about) between two scans. For a horizontal laser that is the
// yaw; for the MAV's downward-looking laser it is the pitch or the roll.
#pragma once

#include <Eigen/Geometry>

#include <deque>
#include <optional>

namespace scanbus::scan_matcher {

// The angle (rad) of the rotation from `from` to `to` about `axis` (unit, in the IMU's
// frame): the twist part of the relative rotation.
double rotation_about(const Eigen::Quaterniond& from, const Eigen::Quaterniond& to, const Eigen::Vector3d& axis);

// The latest orientations, looked up at scan stamps (the last sample at or before it).
class OrientationHistory {
 public:
  explicit OrientationHistory(size_t capacity = 1000) : capacity_(capacity) {}
  void add(double stamp, const Eigen::Quaterniond& orientation);
  std::optional<Eigen::Quaterniond> at(double stamp) const;

 private:
  size_t capacity_;
  std::deque<std::pair<double, Eigen::Quaterniond>> samples_;  // by stamp
};

}  // namespace scanbus::scan_matcher
