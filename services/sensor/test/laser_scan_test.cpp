#include <gtest/gtest.h>

#include <limits>

#include "scanbus/sensor/laser_scan.hpp"

using scanbus::sensor::kept_points;
using scanbus::sensor::LaserScan;
using scanbus::sensor::RangeGate;

// Five rays over 180 degrees, one return each: which the gate keeps, where they lie.
LaserScan five_rays(std::vector<float> ranges) {
  LaserScan scan;
  scan.angle_min = -M_PI / 2;
  scan.angle_increment = M_PI / 4;
  scan.range_min = 0.1;
  scan.range_max = 20;
  scan.ranges = std::move(ranges);
  return scan;
}

TEST(RangeGate, NoReturnAndTheScansOwnLimitsAreLeftOut) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const auto points = kept_points(five_rays({nan, inf, 0.0f, 0.05f, 25.0f}), RangeGate{});
  EXPECT_TRUE(points.empty());
  const auto kept = kept_points(five_rays({1, 2, 3, 4, 5}), RangeGate{});
  ASSERT_EQ(kept.size(), 5u);
  EXPECT_NEAR(kept[0].y(), -1, 1e-12);  // angle -90 degrees
  EXPECT_NEAR(kept[2].x(), 3, 1e-12);   // the middle ray along x
  EXPECT_NEAR(kept[4].y(), 5, 1e-12);
}

TEST(RangeGate, TheGatesLimitsAndOpeningApplyOnTopOfTheScans) {
  RangeGate gate;
  gate.range_min = 1.5;
  gate.range_max = 4.5;
  EXPECT_EQ(kept_points(five_rays({1, 2, 3, 4, 5}), gate).size(), 3u);  // 2, 3 and 4 m
  gate = RangeGate{};
  gate.opening = M_PI / 2;  // the middle ray and the two beside it, 45 degrees either side
  const auto kept = kept_points(five_rays({1, 2, 3, 4, 5}), gate);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_NEAR(kept[1].x(), 3, 1e-12);
  LaserScan unlimited = five_rays({1, 2, 3, 4, 50});
  unlimited.range_max = std::numeric_limits<double>::infinity();  // no limit given: the gate's 30 m holds
  EXPECT_EQ(kept_points(unlimited, RangeGate{}).size(), 4u);
  LaserScan unusable = five_rays({1, 2, 3, 4, 5});
  unusable.range_max = std::nan("");  // a message's limit that is no number keeps nothing
  EXPECT_TRUE(kept_points(unusable, RangeGate{}).empty());
}
