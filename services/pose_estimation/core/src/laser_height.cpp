#include "scanbus/pose_estimation/laser_height.hpp"

#include <algorithm>

namespace scanbus::pose_estimation {

double height_change(double dx, double dy, const Eigen::Quaterniond& attitude_before,
                     const Eigen::Quaterniond& attitude_after, const Eigen::Isometry3d& laser_in_body) {
  const Eigen::Vector3d laser_moved = attitude_before * (laser_in_body.linear() * Eigen::Vector3d(dx, dy, 0));
  // The laser sits off the body's centre: turning moves it without moving the body.
  const Eigen::Vector3d lever_turned =
      (attitude_after * laser_in_body.translation()) - (attitude_before * laser_in_body.translation());
  return (laser_moved - lever_turned).z();
}

std::vector<GroundReturn> ground_returns(const std::vector<Eigen::Vector3d>& points, const Eigen::Quaterniond& attitude,
                                         const Eigen::Vector2d& position, const Eigen::Isometry3d& laser_in_body) {
  std::vector<GroundReturn> returns;
  returns.reserve(points.size());
  for (const auto& point : points) {
    const Eigen::Vector3d below = attitude * (laser_in_body * point);
    returns.push_back({position + below.head<2>(), -below.z()});
  }
  return returns;
}

std::optional<GroundReturn> median_return(std::vector<GroundReturn> returns) {
  if (returns.empty()) return std::nullopt;
  const auto median = returns.begin() + static_cast<long>(returns.size() / 2);
  std::nth_element(returns.begin(), median, returns.end(),
                   [](const GroundReturn& a, const GroundReturn& b) { return a.depth < b.depth; });
  return *median;
}

}  // namespace scanbus::pose_estimation
