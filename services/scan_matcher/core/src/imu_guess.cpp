#include "scanbus/scan_matcher/imu_guess.hpp"

#include <algorithm>
#include <cmath>

namespace scanbus::scan_matcher {

double rotation_about(const Eigen::Quaterniond& from, const Eigen::Quaterniond& to, const Eigen::Vector3d& axis) {
  // Relative rotation in the body frame at `from`; its twist about the axis.
  const Eigen::Quaterniond relative = from.conjugate() * to;
  const double along = relative.vec().dot(axis);
  return std::remainder(2 * std::atan2(along, relative.w()), 2 * M_PI);
}

void OrientationHistory::add(double stamp, const Eigen::Quaterniond& orientation) {
  // Samples arrive in order; an older one (reordered by the network) is put in its place.
  const auto later = std::upper_bound(samples_.begin(), samples_.end(), stamp,
                                      [](double t, const auto& sample) { return t < sample.first; });
  samples_.insert(later, {stamp, orientation.normalized()});
  while (samples_.size() > capacity_) samples_.pop_front();
}

std::optional<Eigen::Quaterniond> OrientationHistory::at(double stamp) const {
  const auto later = std::upper_bound(samples_.begin(), samples_.end(), stamp,
                                      [](double t, const auto& sample) { return t < sample.first; });
  if (later == samples_.begin()) return std::nullopt;
  return std::prev(later)->second;
}

}  // namespace scanbus::scan_matcher
