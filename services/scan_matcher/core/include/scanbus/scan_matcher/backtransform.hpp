// BacktransformLaserScan (MAV paper, Algorithm 3.1), the check of the matcher as it runs:
// scan N+1 is carried back into scan N's frame by the increment the running matcher produced
// for it (what the service publishes), and the distance of each carried point to its nearest
// point of scan N says whether that increment holds. The distance is the plain nearest-point
// one, with no cut-off, so the check does not share the matcher's point-to-line cost, its
// correspondence limit or its trimming.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

#include "scanbus/scan_matcher/laser_log.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"

namespace scanbus::scan_matcher {

struct PairCheck {
  size_t row = 0;   // scans row and row + 1
  Pose2 increment;  // scan N+1 in scan N's frame, as the running matcher made it
  MatchQuality quality = MatchQuality::Ok;
  double median = std::numeric_limits<double>::quiet_NaN();   // m, nearest-point distances
  double p90 = std::numeric_limits<double>::quiet_NaN();      // after back-transformation
  double spacing = std::numeric_limits<double>::quiet_NaN();  // m, scan N's median point spacing
  size_t points = 0;                                          // of scan N+1
  bool suspect = false;  // the match failed, or the median distance is over max_median plus half
                         // the spacing (or there is none)
};

// Scan N+1's points (`scan_n1`, its own frame) against scan N's (`scan_n`) by `increment`.
// `max_median` (m, about the range noise): a median distance larger than it plus half scan N's
// point spacing makes the pair suspect.
PairCheck check_pair(const std::vector<Eigen::Vector2d>& scan_n, const std::vector<Eigen::Vector2d>& scan_n1,
                     const Pose2& increment, MatchQuality quality, double max_median);

// The log tracked from its first scan with `settings` (with the wheel odometry as the guess
// when `odometry_guess`), and every consecutive pair checked. `progress(done, total)` as the
// scans are tracked.
std::vector<PairCheck> check_log(const MatcherSettings& settings, const std::vector<LaserRecord>& records,
                                 bool odometry_guess, double max_median,
                                 const std::function<void(size_t, size_t)>& progress = {});

// Points of scan N+1 carried back into scan N's frame by the match's increment.
std::vector<Eigen::Vector2d> carried_back(const std::vector<Eigen::Vector2d>& points, const Pose2& increment);

// The value `share` (0..1) of the way up the sorted values; NaN for none.
double percentile(std::vector<double> values, double share);

}  // namespace scanbus::scan_matcher
