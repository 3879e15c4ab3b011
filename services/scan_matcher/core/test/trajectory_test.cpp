#include "scanbus/scan_matcher/trajectory.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "laser_world.hpp"

using namespace scanbus::scan_matcher;
using scanbus::test_support::LaserWorld;

namespace {

std::string temporary(const std::string& name) { return "/tmp/scanbus_trajectory_" + std::to_string(getpid()) + name; }

std::string error_of(const std::string& path) {
  try {
    read_trajectory(path);
  } catch (const LogError& error) {
    return error.what();
  }
  return "";
}

}  // namespace

TEST(Trajectory, SurvivesItsFile) {
  const std::string path = temporary("round.txt");
  const Trajectory written{{1.5, 2.25}, {{0.1, -0.2, 0.3}, {1.234567, 2, -3.1}}};
  write_trajectory(path, written);
  const Trajectory read = read_trajectory(path);
  ASSERT_EQ(read.poses.size(), 2u);
  EXPECT_EQ(read.stamps, written.stamps);
  EXPECT_NEAR(read.poses[1].x, 1.234567, 1e-9);
  EXPECT_NEAR(read.poses[1].theta, -3.1, 1e-9);
  std::remove(path.c_str());
}

TEST(Trajectory, AMalformedLineIsNamed) {
  const std::string path = temporary("bad.txt");
  std::ofstream(path) << "# stamp x y theta\n1 0 0 0\n2 0.5 zero 0\n";
  EXPECT_EQ(error_of(path), path + ":3: expected 'stamp x y theta'");
  EXPECT_EQ(error_of(temporary("missing.txt")), temporary("missing.txt") + ": cannot open");
  std::remove(path.c_str());
}

// A robot driving through the room: the log's trajectory follows it, with or without the
// odometry as each match's guess.
TEST(Trajectory, TrackingALogFollowsTheRobot) {
  const LaserWorld room = LaserWorld::room();
  std::mt19937 random(5);
  const Pose2 step{0.05, 0.0, 1 * M_PI / 180};
  std::vector<LaserRecord> records;
  Pose2 truth{-1, -0.5, 0};
  for (int i = 0; i < 30; ++i, truth = truth * step) records.push_back({room.scan(truth, {}, random), truth});
  for (int k = 0; k < 30; ++k) records[k].scan.stamp = 0.1 * k;
  for (const bool odometry_guess : {false, true}) {
    ScanMatcher matcher;
    size_t calls = 0;
    const TrackedLog tracked = track_log(matcher, records, odometry_guess, [&](size_t done, size_t total) {
      EXPECT_EQ(done, ++calls);
      EXPECT_EQ(total, 30u);
    });
    EXPECT_EQ(calls, 30u);
    EXPECT_EQ(tracked.failed, 0u);
    ASSERT_EQ(tracked.trajectory.poses.size(), 30u);
    EXPECT_DOUBLE_EQ(tracked.trajectory.stamps.back(), 2.9);
    // Relative to the first scan: 29 steps of 5 cm turning 1 degree each.
    Pose2 expected{};
    for (int i = 0; i < 29; ++i) expected = expected * step;
    const Pose2 last = tracked.trajectory.poses.back();
    EXPECT_NEAR(last.x, expected.x, 0.05) << odometry_guess;
    EXPECT_NEAR(last.y, expected.y, 0.05) << odometry_guess;
    EXPECT_NEAR(last.theta, expected.theta, 1 * M_PI / 180) << odometry_guess;
  }
}
