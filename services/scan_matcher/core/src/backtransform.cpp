#include "scanbus/scan_matcher/backtransform.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "nearest_points.hpp"
#include "scanbus/scan_matcher/trajectory.hpp"

namespace scanbus::scan_matcher {

double percentile(std::vector<double> values, double share) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto at = values.begin() + static_cast<long>(share * static_cast<double>(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

PairCheck check_pair(const std::vector<Eigen::Vector2d>& scan_n, const std::vector<Eigen::Vector2d>& scan_n1,
                     const Pose2& increment, MatchQuality quality, double max_median) {
  PairCheck check;
  check.increment = increment;
  check.quality = quality;
  std::vector<double> distances;
  if (!scan_n.empty()) {
    const NearestPoints search(scan_n);
    for (const auto& point : carried_back(scan_n1, increment))
      distances.push_back(std::sqrt(search.nearest(point).distance_squared));
  }
  check.points = distances.size();
  check.median = percentile(distances, 0.5);
  check.p90 = percentile(distances, 0.9);
  // A point on a surface scan N sampled every `spacing` lies up to half of that from its nearest
  // point even when the increment is exact: sparser rays are allowed more.
  std::vector<double> gaps;
  for (size_t i = 0; i + 1 < scan_n.size(); ++i) gaps.push_back((scan_n[i + 1] - scan_n[i]).norm());
  check.spacing = percentile(gaps, 0.5);
  check.suspect = quality != MatchQuality::Ok || !(check.median <= max_median + check.spacing / 2);
  return check;
}

std::vector<PairCheck> check_log(const MatcherSettings& settings, const std::vector<LaserRecord>& records,
                                 bool odometry_guess, double max_median,
                                 const std::function<void(size_t, size_t)>& progress) {
  ScanMatcher matcher(settings);
  std::vector<PairCheck> checks;
  const auto tracked = track_log(matcher, records, odometry_guess, progress);
  const auto& poses = tracked.trajectory.poses;
  std::vector<Eigen::Vector2d> scan_n =
      records.empty() ? std::vector<Eigen::Vector2d>{} : matcher.points_of(records[0].scan);
  for (size_t row = 0; row + 1 < records.size(); ++row) {
    std::vector<Eigen::Vector2d> scan_n1 = matcher.points_of(records[row + 1].scan);  // each scan's points once
    checks.push_back(
        check_pair(scan_n, scan_n1, poses[row].inverse() * poses[row + 1], tracked.qualities[row + 1], max_median));
    checks.back().row = row;
    scan_n = std::move(scan_n1);
  }
  return checks;
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
