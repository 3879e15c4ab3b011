#include "scanbus/scan_matcher/backtransform.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "laser_world.hpp"

using namespace scanbus::scan_matcher;
using scanbus::test_support::LaserWorld;

TEST(Backtransform, ARightMatchLiesOnTheScanBefore) {
  const LaserWorld room = LaserWorld::room();
  std::mt19937 random(3);
  const ScanMatcher matcher;
  const Pose2 start{0.2, -0.3, 0.4}, motion{0.15, 0.03, 3 * M_PI / 180};
  const PairCheck check =
      check_pair(matcher, room.scan(start, {}, random), room.scan(start * motion, {}, random), 0.03);
  EXPECT_FALSE(check.suspect);
  EXPECT_EQ(check.match.quality, MatchQuality::Ok);
  EXPECT_GT(check.points, 200u);
  EXPECT_LT(check.median, 0.02);  // 2 cm range noise, measured across the line
  EXPECT_LE(check.median, check.p90);
}

// Scan N+1 from another building: whatever the matcher makes of it does not lie on scan N.
TEST(Backtransform, ScansThatDoNotBelongTogetherAreSuspect) {
  std::mt19937 random(4);
  const ScanMatcher matcher;
  const PairCheck check = check_pair(matcher, LaserWorld::room().scan({0, 0, 0}, {}, random),
                                     LaserWorld::corridor().scan({3, 0.1, 0}, {}, random), 0.03);
  EXPECT_TRUE(check.suspect);
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
