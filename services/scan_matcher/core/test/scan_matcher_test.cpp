#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>

#include "scanbus/scan_matcher/laser_log.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"

using namespace scanbus::scan_matcher;

namespace {

// A 2D room (walls and a pillar) and a 361-ray, 180 degree laser in it.
struct Room2D {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> walls = {
      {{-3, -2}, {4, -2}}, {{4, -2}, {4, 3}}, {{4, 3}, {-3, 3}}, {{-3, 3}, {-3, -2}},
      {{1, 0.5}, {1.6, 0.5}}, {{1.6, 0.5}, {1.6, 1.2}}, {{1.6, 1.2}, {1, 1.2}}, {{1, 1.2}, {1, 0.5}}};

  Scan scan(const Pose2& pose, double noise, unsigned seed) const {
    std::mt19937 random(seed);
    std::normal_distribution<double> jitter(0, noise);
    Scan scan{-M_PI / 2, M_PI / 360, {}};
    for (int i = 0; i < 361; ++i) {
      const double angle = pose.theta + scan.angle_min + i * scan.angle_increment;
      const Eigen::Vector2d origin(pose.x, pose.y), ray(std::cos(angle), std::sin(angle));
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& [a, b] : walls) {
        const Eigen::Vector2d edge = b - a, to_a = a - origin;
        const double d = ray.x() * edge.y() - ray.y() * edge.x();
        if (std::abs(d) < 1e-12) continue;
        const double t = (to_a.x() * edge.y() - to_a.y() * edge.x()) / d;
        const double s = (to_a.x() * ray.y() - to_a.y() * ray.x()) / d;
        if (t > 0 && s >= 0 && s <= 1) nearest = std::min(nearest, t);
      }
      scan.ranges.push_back(static_cast<float>(nearest + jitter(random)));
    }
    return scan;
  }
};

std::string temp_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(Pose2, ComposeAndInvert) {
  const Pose2 a{1, 2, 0.5}, b{-0.3, 0.7, -1.2};
  const Pose2 identity = a * a.inverse();
  EXPECT_NEAR(identity.x, 0, 1e-12);
  EXPECT_NEAR(identity.theta, 0, 1e-12);
  const Pose2 back = a.inverse() * (a * b);
  EXPECT_NEAR(back.x, b.x, 1e-12);
  EXPECT_NEAR(back.y, b.y, 1e-12);
  EXPECT_NEAR(back.theta, b.theta, 1e-12);
}

TEST(PlIcp, RecoversKnownMotionWithinACentimetreAndTwoTenthsOfADegree) {
  const Room2D room;
  ScanMatcher matcher;
  const Pose2 start{0, 0, 0.1}, motion{0.25, -0.08, 4 * M_PI / 180};
  const auto reference = matcher.points_of(room.scan(start, 0.02, 1));
  const auto moved = matcher.points_of(room.scan(start * motion, 0.02, 2));
  const MatchResult result = matcher.align(reference, moved, Pose2{});  // no guess at all
  ASSERT_EQ(result.quality, MatchQuality::Ok);
  EXPECT_NEAR(result.increment.x, motion.x, 0.01);
  EXPECT_NEAR(result.increment.y, motion.y, 0.01);
  EXPECT_NEAR(result.increment.theta * 180 / M_PI, motion.theta * 180 / M_PI, 0.2);
  EXPECT_GT(result.correspondences, 200u);
  EXPECT_GT(result.covariance(0, 0), 0);
  EXPECT_LT(result.residual, 0.03);
}

TEST(PlIcp, TrajectoryThroughKeyframes) {
  const Room2D room;
  ScanMatcher matcher;
  Pose2 truth{-1, -0.5, 0};
  const Pose2 step{0.05, 0.01, 1.5 * M_PI / 180};
  matcher.add_scan(room.scan(truth, 0.01, 0));
  MatchResult last;
  int keyframes = 0;
  for (unsigned i = 1; i <= 30; ++i) {
    truth = truth * step;
    last = matcher.add_scan(room.scan(truth, 0.01, i));
    ASSERT_EQ(last.quality, MatchQuality::Ok) << "scan " << i;
    keyframes += last.keyframe;
  }
  const Pose2 travelled = Pose2{-1, -0.5, 0}.inverse() * truth;
  EXPECT_NEAR(last.pose.x, travelled.x, 0.03);
  EXPECT_NEAR(last.pose.y, travelled.y, 0.03);
  EXPECT_NEAR(last.pose.theta, travelled.theta, 0.5 * M_PI / 180);
  EXPECT_GT(keyframes, 3);
  EXPECT_LT(keyframes, 30);
}

TEST(PlIcp, BadRangesAreDroppedAndTooFewPointsHoldThePose) {
  ScanMatcher matcher;
  Scan scan{-M_PI / 2, M_PI / 4, {1.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f,
                                  std::numeric_limits<float>::infinity(), 45.0f}};
  EXPECT_EQ(matcher.points_of(scan).size(), 1u);  // NaN, zero, inf and beyond 30 m dropped
  matcher.add_scan(scan);
  const MatchResult result = matcher.add_scan(scan);
  EXPECT_EQ(result.quality, MatchQuality::TooFewCorrespondences);
  EXPECT_EQ(result.pose.x, 0.0);
  EXPECT_EQ(result.pose.theta, 0.0);
}

TEST(LaserLog, ReadsFlaserAndRobotLaser) {
  const std::string path = temp_file("log.clf",
                                     "# a comment\n"
                                     "ODOM 1 2 3 0 0 0 100.0 host 100.0\n"
                                     "FLASER 3 1.0 2.0 3.0 9 9 9 1.5 2.5 0.1 100.25 host 100.3\n"
                                     "ROBOTLASER1 0 -1.57 3.14 0.01 30 0.01 0 3 1.0 2.0 3.0 0 0 0 0 4.5 5.5 0.2 "
                                     "0 0 0 0 0 101.5 host 101.6\n");
  const auto records = read_carmen_log(path);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].ranges.size(), 3u);
  EXPECT_DOUBLE_EQ(records[0].stamp, 100.25);
  EXPECT_DOUBLE_EQ(records[0].odometry.x, 1.5);  // odometry, not the corrected pose (9 9 9)
  EXPECT_NEAR(records[0].angle_increment, M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(records[1].stamp, 101.5);
  EXPECT_DOUBLE_EQ(records[1].odometry.y, 5.5);
  EXPECT_DOUBLE_EQ(records[1].angle_min, -1.57);
}

TEST(LaserLog, MalformedLinesAreNamed) {
  try {
    read_carmen_log(temp_file("bad.clf", "FLASER 3 1.0 2.0\n"));
    FAIL() << "no error";
  } catch (const LogError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.clf:1: cannot read"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_carmen_log(temp_file("none.clf", "ODOM 1 2 3\n")), LogError);
  EXPECT_THROW(read_carmen_log("/nonexistent.clf"), LogError);
  EXPECT_THROW(read_relations(temp_file("bad.relations", "1 2 3\n")), LogError);
}

TEST(Relations, MetricOfKuemmerle) {
  const std::string path = temp_file("r.relations", "10 11 1.0 0 0 0 0 0.1\n10 12 2.0 0 0 0 0 0\n99 100 1 0 0 0 0 0\n");
  const auto relations = read_relations(path);
  ASSERT_EQ(relations.size(), 3u);
  const std::vector<double> stamps = {10, 11, 12};
  std::vector<Pose2> poses = {{5, 5, 0}, {6, 5, 0.1}, {7, 5, 0}};
  RelationErrors errors = evaluate_relations(stamps, poses, relations);
  EXPECT_EQ(errors.translational.count, 2u);
  EXPECT_EQ(errors.missing, 1u);
  EXPECT_NEAR(errors.translational.max, 0, 1e-12);
  poses[2].x = 7.1;  // 10 cm off at t = 12
  errors = evaluate_relations(stamps, poses, relations);
  EXPECT_NEAR(errors.translational.max, 0.1, 1e-12);
  EXPECT_NEAR(errors.translational.mean, 0.05, 1e-12);
  EXPECT_EQ(evaluate_relations(stamps, poses, relations, 1.5).translational.count, 1u);
}
