#include "scanbus/scan_matcher/backtransform.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "laser_world.hpp"
#include "scanbus/scan_matcher/laser_log.hpp"

using namespace scanbus::scan_matcher;
using scanbus::test_support::LaserWorld;

namespace {

// A flight through the room as a log: scans 0.05 m and 1 degree apart, odometry exact.
std::vector<LaserRecord> room_log(int scans) {
  const LaserWorld room = LaserWorld::room();
  std::mt19937 random(3);
  std::vector<LaserRecord> records;
  Pose2 truth{-1.5, -0.5, 0.2};
  for (int i = 0; i < scans; ++i, truth = truth * Pose2{0.05, 0, M_PI / 180}) {
    records.push_back({room.scan(truth, {}, random), truth});
    records.back().scan.stamp = i * 0.1;
  }
  return records;
}

}  // namespace

// Every increment of the running matcher lies on the scan before: nearest points within the
// spacing of the rays and the 2 cm range noise.
TEST(Backtransform, TheRunningMatchersIncrementsLieOnTheScanBefore) {
  const auto checks = check_log(MatcherSettings{}, room_log(30), false, 0.03);
  ASSERT_EQ(checks.size(), 29u);
  for (const auto& check : checks) {
    EXPECT_FALSE(check.suspect) << "pair " << check.row << ": median " << check.median;
    EXPECT_EQ(check.quality, MatchQuality::Ok);
    EXPECT_GT(check.points, 300u);  // every point carried back, none cut off
    EXPECT_LE(check.median, check.p90);
    EXPECT_NEAR(check.increment.x, 0.05, 0.01);
  }
}

// The check scores the increment it is given, not a fresh alignment: the true increment
// passes, one 10 cm off does not, whatever a matcher would make of the pair.
TEST(Backtransform, AWrongIncrementIsSuspect) {
  const auto records = room_log(2);
  const ScanMatcher matcher;
  const auto scan_n = matcher.points_of(records[0].scan), scan_n1 = matcher.points_of(records[1].scan);
  const Pose2 truth{0.05, 0, M_PI / 180};
  const PairCheck right = check_pair(scan_n, scan_n1, truth, MatchQuality::Ok, 0.03);
  const PairCheck wrong = check_pair(scan_n, scan_n1, truth * Pose2{0.1, 0.1, 0}, MatchQuality::Ok, 0.03);
  EXPECT_FALSE(right.suspect) << right.median;
  EXPECT_TRUE(wrong.suspect) << wrong.median;
  EXPECT_GT(wrong.median, 2 * right.median);
  EXPECT_TRUE(check_pair(scan_n, scan_n1, truth, MatchQuality::Diverged, 0.03).suspect);  // a failed match
}

TEST(Backtransform, CarriesPointsBackByTheIncrement) {
  const auto moved = carried_back({{1, 0}, {0, 2}}, Pose2{1, 0, M_PI / 2});
  ASSERT_EQ(moved.size(), 2u);
  EXPECT_TRUE(moved[0].isApprox(Eigen::Vector2d(1, 1)));
  EXPECT_TRUE(moved[1].isApprox(Eigen::Vector2d(-1, 0)));
}

TEST(Backtransform, Percentiles) {
  EXPECT_EQ(percentile({3, 1, 2}, 0.5), 2);
  EXPECT_EQ(percentile({3, 1, 2, 10}, 1.0), 10);
  EXPECT_TRUE(std::isnan(percentile({}, 0.5)));
}
