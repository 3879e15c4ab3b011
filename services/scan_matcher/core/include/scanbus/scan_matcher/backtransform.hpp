// BacktransformLaserScan (MAV paper, Algorithm 3.1), the check of one match: scan N+1 is
// matched to scan N, carried back by the matched increment, and the distances of its points
// to scan N's surface (point to line, as PL-ICP measures them) say whether the match holds.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <limits>
#include <vector>

#include "scanbus/scan_matcher/pl_icp.hpp"
#include "scanbus/sensor/laser_scan.hpp"

namespace scanbus::scan_matcher {

struct PairCheck {
  MatchResult match;                                         // scan N+1 in scan N's frame
  double median = std::numeric_limits<double>::quiet_NaN();  // m, point-to-line residuals
  double p90 = std::numeric_limits<double>::quiet_NaN();     // after back-transformation
  size_t points = 0;                                         // with a residual
  bool suspect = false;  // the match failed, or the median residual is over the limit (or none)
};

// `max_median` (m): a larger median residual makes the pair suspect.
PairCheck check_pair(const ScanMatcher& matcher, const sensor::LaserScan& scan_n, const sensor::LaserScan& scan_n1,
                     double max_median);

// Points of scan N+1 carried back into scan N's frame by the match's increment.
std::vector<Eigen::Vector2d> carried_back(const std::vector<Eigen::Vector2d>& points, const Pose2& increment);

// The value `share` (0..1) of the way up the sorted values; NaN for none.
double percentile(std::vector<double> values, double share);

}  // namespace scanbus::scan_matcher
