#include "scanbus/scan_matcher/backtransform.hpp"

#include <Eigen/Geometry>

#include <algorithm>

namespace scanbus::scan_matcher {

double percentile(std::vector<double> values, double share) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto at = values.begin() + static_cast<long>(share * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

PairCheck check_pair(const ScanMatcher& matcher, const sensor::LaserScan& scan_n, const sensor::LaserScan& scan_n1,
                     double max_median) {
  const auto reference = matcher.points_of(scan_n);
  const auto scan = matcher.points_of(scan_n1);
  PairCheck check;
  check.match = matcher.align(reference, scan, Pose2{});
  const std::vector<double> residuals = matcher.residuals(reference, scan, check.match.increment);
  check.points = residuals.size();
  check.median = percentile(residuals, 0.5);
  check.p90 = percentile(residuals, 0.9);
  check.suspect = check.match.quality != MatchQuality::Ok || !(check.median <= max_median);
  return check;
}

std::vector<Eigen::Vector2d> carried_back(const std::vector<Eigen::Vector2d>& points, const Pose2& increment) {
  const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(increment.theta).toRotationMatrix();
  const Eigen::Vector2d translation(increment.x, increment.y);
  std::vector<Eigen::Vector2d> moved;
  moved.reserve(points.size());
  for (const auto& p : points) moved.push_back(rotation * p + translation);
  return moved;
}

}  // namespace scanbus::scan_matcher
