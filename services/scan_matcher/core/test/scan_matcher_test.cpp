#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>

#include "laser_world.hpp"
#include "scanbus/scan_matcher/imu_guess.hpp"
#include "scanbus/scan_matcher/laser_log.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"

using namespace scanbus::scan_matcher;
using scanbus::test_support::LaserModel;
using scanbus::test_support::LaserWorld;

namespace {

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
  const LaserWorld room = LaserWorld::room();
  std::mt19937 random(1);
  ScanMatcher matcher;
  const Pose2 start{0, 0, 0.1}, motion{0.25, -0.08, 4 * M_PI / 180};
  const auto reference = matcher.points_of(room.scan(start, {}, random));
  const auto moved = matcher.points_of(room.scan(start * motion, {}, random));
  const MatchResult result = matcher.align(reference, moved, Pose2{});  // no guess at all
  ASSERT_EQ(result.quality, MatchQuality::Ok);
  EXPECT_NEAR(result.increment.x, motion.x, 0.01);
  EXPECT_NEAR(result.increment.y, motion.y, 0.01);
  EXPECT_NEAR(result.increment.theta * 180 / M_PI, motion.theta * 180 / M_PI, 0.2);
  EXPECT_GT(result.correspondences, 200u);
  EXPECT_GT(result.covariance(0, 0), 0);
  EXPECT_LT(result.residual, 0.03);
}

namespace {

struct Flight {
  Pose2 start, step;  // the laser's first pose and its motion per scan, in its own frame
  int scans = 40;
  std::optional<Pose2> guess;  // given to every match (odometry, IMU), else none
};

// Per-scan increment errors: root mean square and worst, per laser axis and in rotation.
struct FlightErrors {
  Eigen::Vector3d rms = Eigen::Vector3d::Zero();  // x (m), y (m), theta (deg)
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();
  int failed = 0, keyframes = 0;
  Eigen::Matrix3d covariance;  // of the last match
};

// Flies the laser through the world with 2 cm range noise and compares every matched
// increment with the true one.
FlightErrors fly(const LaserWorld& world, const Flight& flight, const LaserModel& laser) {
  std::mt19937 random(7);
  ScanMatcher matcher;
  FlightErrors errors;
  Pose2 truth = flight.start;
  matcher.add_scan(world.scan(truth, laser, random));
  for (int i = 1; i < flight.scans; ++i) {
    truth = truth * flight.step;
    const MatchResult result = matcher.add_scan(world.scan(truth, laser, random), flight.guess);
    errors.failed += result.quality != MatchQuality::Ok;
    errors.keyframes += result.keyframe;
    const Pose2 error = flight.step.inverse() * result.increment;
    const Eigen::Vector3d e(std::abs(error.x), std::abs(error.y), std::abs(error.theta) * 180 / M_PI);
    errors.rms += e.cwiseProduct(e);
    errors.worst = errors.worst.cwiseMax(e);
    errors.covariance = result.covariance;
  }
  errors.rms = (errors.rms / (flight.scans - 1)).cwiseSqrt();
  std::printf("increment errors (x m, y m, theta deg): rms %.4f %.4f %.3f, worst %.4f %.4f %.3f\n", errors.rms.x(),
              errors.rms.y(), errors.rms.z(), errors.worst.x(), errors.worst.y(), errors.worst.z());
  return errors;
}

// Issue 5: increments within 1 cm and 0.2 degrees at 2 cm range noise, read as the root
// mean square over a flight; no single scan may be off by more than 2.5 cm or 0.5 degrees.
void expect_within_targets(const FlightErrors& errors) {
  EXPECT_EQ(errors.failed, 0);
  EXPECT_LT(errors.rms.x(), 0.01) << errors.rms.transpose();
  EXPECT_LT(errors.rms.y(), 0.01) << errors.rms.transpose();
  EXPECT_LT(errors.rms.z(), 0.2) << errors.rms.transpose();
  EXPECT_LT(errors.worst.head<2>().maxCoeff(), 0.025) << errors.worst.transpose();
  EXPECT_LT(errors.worst.z(), 0.5) << errors.worst.transpose();
}

}  // namespace

TEST(PlIcpSynthetic, Room) {
  const FlightErrors errors =
      fly(LaserWorld::room(), {{-1.5, -0.5, 0.2}, {0.06, 0.01, 2 * M_PI / 180}, 40, std::nullopt}, {});
  expect_within_targets(errors);
  EXPECT_GT(errors.keyframes, 3);
}

TEST(PlIcpSynthetic, CorridorWithDoorRecesses) {
  expect_within_targets(
      fly(LaserWorld::corridor(), {{0, 0.1, 0.05}, {0.15, 0.0, -0.3 * M_PI / 180}, 60, std::nullopt}, {}));
}

// The MAV's laser looks down (x axis at -90 degrees in the x-forward, y-up plane), 90 degree
// opening in 0.25 degree steps as in the paper, flying forward while climbing and pitching.
LaserModel downward_laser() {
  LaserModel laser;
  laser.angle_min = -M_PI / 4;
  laser.angle_increment = M_PI / 720;
  laser.rays = 361;
  return laser;
}

TEST(PlIcpSynthetic, DownwardOverSteppedGround) {
  // Forward 0.1 m and up 0.02 m per scan, pitching 0.5 degrees: in the laser's frame (x down,
  // y forward) that is x = -0.02, y = 0.1.
  const Pose2 start{0, 3.0, -M_PI / 2}, step{-0.02, 0.1, 0.5 * M_PI / 180};
  expect_within_targets(fly(LaserWorld::stepped_ground(), {start, step, 60, std::nullopt}, downward_laser()));
}

TEST(PlIcpSynthetic, DownwardOverFlatGroundRecoversHeightAndPitch) {
  // Flat ground constrains only the distance to it (laser x: the height) and the pitch; the
  // motion along the ground comes from the guess (IMU, GPS) and the covariance says so.
  const Pose2 start{0, 3.0, -M_PI / 2}, step{-0.02, 0.1, 0.3 * M_PI / 180};
  const FlightErrors errors = fly(LaserWorld::flat_ground(), {start, step, 40, step}, downward_laser());
  EXPECT_EQ(errors.failed, 0);
  EXPECT_LT(errors.rms.x(), 0.01) << errors.rms.transpose();
  EXPECT_LT(errors.rms.z(), 0.2) << errors.rms.transpose();
  EXPECT_LT(errors.worst.x(), 0.025) << errors.worst.transpose();
  EXPECT_GT(errors.covariance(1, 1), 100 * errors.covariance(0, 0)) << errors.covariance;
}

// 160 scans 0.15 m apart down the corridor (24 m, each a keyframe): a map of the latest 40
// keyframes stops growing once it has them, one point per 5 cm cell; a map keeping every
// keyframe grows with the distance travelled.
TEST(ScanToMap, TheMapStaysBoundedWhereverTheSensorGoes) {
  const auto fly = [](int map_keyframes) {
    const LaserWorld corridor = LaserWorld::corridor();
    std::mt19937 random(5);
    MatcherSettings settings;
    settings.keyframe_distance = 0.1;  // every scan
    settings.map_keyframes = map_keyframes;
    ScanMatcher matcher(settings);
    Pose2 truth{-4, 0.1, 0};
    std::vector<size_t> sizes;  // after each keyframe
    for (int i = 0; i < 160; ++i, truth = truth * Pose2{0.15, 0, 0}) {
      const MatchResult result = matcher.add_scan(corridor.scan(truth, {}, random), Pose2{0.15, 0, 0});
      EXPECT_TRUE(i == 0 || result.quality == MatchQuality::Ok) << "scan " << i;
      if (result.keyframe) sizes.push_back(matcher.map_points());
    }
    // Along the corridor only the recesses' sides hold the match, and they pull it forward:
    // 0.15 m over 24 m with 40 keyframes, 0.11 m pairwise (1 keyframe), 0.31 m here.
    EXPECT_NEAR(matcher.pose().x, 159 * 0.15, 0.5) << map_keyframes;
    return sizes;
  };
  const std::vector<size_t> bounded = fly(40), unbounded = fly(1000);
  ASSERT_EQ(bounded.size(), 160u);
  const size_t filled = *std::max_element(bounded.begin(), bounded.begin() + 45);
  EXPECT_LT(*std::max_element(bounded.begin() + 45, bounded.end()), 1.2 * filled);
  EXPECT_GT(unbounded.back(), 2 * bounded.back());
  EXPECT_LT(unbounded.back(), 160 * 361 / 10);  // thinned: walls seen again fill no new cells
}

// Odometry that jumps (50 degrees in one scan, as MIT CSAIL's wheel odometry does at scan
// 325) is dropped for the constant velocity: the match is the one made without any guess.
TEST(ScanToMap, OdometryThatJumpsIsNotFollowed) {
  const LaserWorld room = LaserWorld::room();
  const Pose2 step{0.05, 0, 1 * M_PI / 180};
  ScanMatcher with_jump, without;
  std::mt19937 random(9);
  Pose2 truth{-1.5, -0.5, 0.2};
  for (int i = 0; i < 20; ++i) {
    const auto scan = room.scan(truth, {}, random);
    const bool jump = i == 12;
    const MatchResult a = with_jump.add_scan(scan, jump ? Pose2{0.8, 0.02, 50 * M_PI / 180} : step);
    const MatchResult b = without.add_scan(scan, jump ? std::nullopt : std::optional<Pose2>(step));
    ASSERT_EQ(a.pose.x, b.pose.x) << "scan " << i;
    ASSERT_EQ(a.pose.theta, b.pose.theta) << "scan " << i;
    truth = truth * step;
  }
}

// The caller's guess (odometry) pulls with guess_weight, the constant-velocity prediction with
// prior_weight: a guess 4 cm off, weighed heavily, holds the match there; weighed zero, the
// scan decides, however heavy the constant-velocity prior.
TEST(ScanToMap, AGuessPullsWithItsOwnWeight) {
  const LaserWorld room = LaserWorld::room();
  const Pose2 start{-1.5, -0.5, 0.2}, step{0.05, 0, 1 * M_PI / 180}, guess{0.09, 0, 1 * M_PI / 180};
  const auto matched_x = [&](double guess_weight, double prior_weight) {
    MatcherSettings settings;
    settings.guess_weight = guess_weight;
    settings.prior_weight = prior_weight;
    ScanMatcher matcher(settings);
    std::mt19937 random(13);
    matcher.add_scan(room.scan(start, {}, random));
    const MatchResult result = matcher.add_scan(room.scan(start * step, {}, random), guess);
    EXPECT_EQ(result.quality, MatchQuality::Ok);
    return result.increment.x;
  };
  EXPECT_NEAR(matched_x(1e6, 0), guess.x, 0.005);
  EXPECT_NEAR(matched_x(0, 1e6), step.x, 0.01);
}

// Scans of another place entirely (the sensor carried elsewhere): the matches fail, and
// after lost_after of them the map starts again from the scan, so matching goes on.
TEST(ScanToMap, ALostMatcherStartsItsMapAgain) {
  const LaserWorld room = LaserWorld::room(), corridor = LaserWorld::corridor();
  std::mt19937 random(11);
  MatcherSettings settings;
  settings.lost_after = 5;
  ScanMatcher matcher(settings);
  Pose2 truth{-1.5, -0.5, 0.2};
  for (int i = 0; i < 10; ++i, truth = truth * Pose2{0.05, 0, 0}) matcher.add_scan(room.scan(truth, {}, random));
  Pose2 elsewhere{-10, 0.1, 0};
  int failed = 0, restarted_at = -1;
  for (int i = 0; i < 20; ++i, elsewhere = elsewhere * Pose2{0.1, 0, 0}) {
    const MatchResult result = matcher.add_scan(corridor.scan(elsewhere, {}, random));
    if (result.quality != MatchQuality::Ok) ++failed;
    if (result.quality != MatchQuality::Ok && result.keyframe && restarted_at < 0) restarted_at = i;
    if (restarted_at >= 0 && i > restarted_at + 1) {
      EXPECT_EQ(result.quality, MatchQuality::Ok) << "scan " << i;
    }
  }
  EXPECT_EQ(restarted_at, 4);  // the fifth failure in a row
  EXPECT_EQ(failed, 5);
}

TEST(PlIcp, BadRangesAreDroppedAndTooFewPointsStartNoMap) {
  ScanMatcher matcher;
  scanbus::sensor::LaserScan scan;
  scan.angle_min = -M_PI / 2;
  scan.angle_increment = M_PI / 4;
  scan.ranges = {1.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f, std::numeric_limits<float>::infinity(), 45.0f};
  EXPECT_EQ(matcher.points_of(scan).size(), 1u);  // NaN, zero, inf and beyond 30 m dropped
  for (int i = 0; i < 2; ++i) {
    const MatchResult result = matcher.add_scan(scan);
    EXPECT_EQ(result.quality, MatchQuality::NoReference);
    EXPECT_FALSE(result.keyframe);  // one point is no map to match against
    EXPECT_EQ(result.pose.x, 0.0);
    EXPECT_EQ(result.pose.theta, 0.0);
  }
  // The first usable scan starts the map; the next one matches against it.
  const LaserWorld room = LaserWorld::room();
  std::mt19937 random(2);
  EXPECT_TRUE(matcher.add_scan(room.scan({0, 0, 0}, {}, random)).keyframe);
  EXPECT_EQ(matcher.add_scan(room.scan({0.05, 0, 0}, {}, random)).quality, MatchQuality::Ok);
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
  EXPECT_EQ(records[0].scan.ranges.size(), 3u);
  EXPECT_DOUBLE_EQ(records[0].scan.stamp, 100.25);
  EXPECT_DOUBLE_EQ(records[0].odometry.x, 1.5);  // odometry, not the corrected pose (9 9 9)
  EXPECT_NEAR(records[0].scan.angle_increment, M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(records[1].scan.stamp, 101.5);
  EXPECT_DOUBLE_EQ(records[1].odometry.y, 5.5);
  EXPECT_DOUBLE_EQ(records[1].scan.angle_min, -1.57);
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

TEST(ImuGuess, TurnAboutTheLaserAxis) {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  const Eigen::Quaterniond level(AngleAxisd(0.3, Vector3d::UnitZ()));
  // Yawing by 5 degrees while pitching: a horizontal laser sees the yaw only.
  const Eigen::Quaterniond turned =
      level * Eigen::Quaterniond(AngleAxisd(5 * M_PI / 180, Vector3d::UnitZ()) * AngleAxisd(0.01, Vector3d::UnitY()));
  EXPECT_NEAR(rotation_about(level, turned, Vector3d::UnitZ()), 5 * M_PI / 180, 1e-3);
  // A downward laser whose scan plane turns with the pitch (its z axis along the body's y).
  const Eigen::Quaterniond pitched = level * Eigen::Quaterniond(AngleAxisd(-0.05, Vector3d::UnitY()));
  EXPECT_NEAR(rotation_about(level, pitched, Vector3d::UnitY()), -0.05, 1e-9);
  EXPECT_NEAR(rotation_about(level, pitched, Vector3d::UnitZ()), 0, 1e-9);
}

TEST(ImuGuess, HistoryGivesTheLastSampleAtOrBeforeAStamp) {
  OrientationHistory history(3);
  EXPECT_FALSE(history.at(1.0));
  for (int i = 1; i <= 4; ++i) history.add(i, Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ())));
  EXPECT_FALSE(history.at(1.5)) << "sample 1 fell out of the bounded history";
  EXPECT_NEAR(Eigen::AngleAxisd(*history.at(3.5)).angle(), 0.3, 1e-12);
  history.add(3.2, Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ())));  // arrived late
  EXPECT_NEAR(Eigen::AngleAxisd(*history.at(3.5)).angle(), 0.7, 1e-12);
}

// Flat ground seen from above pins only the height and the pitch. One match pulled 0.1 m
// along the ground (a wrong guess) is carried on at every scan by the constant-velocity
// prediction; predicting no motion (the MAV's setting), the pose stays where it was.
TEST(PlIcpSynthetic, WithoutConstantVelocityAWrongSlideIsNotCarriedOn) {
  const LaserWorld ground = LaserWorld::flat_ground();
  const Pose2 hovering{0, 3.0, -M_PI / 2};
  const auto slide_after_the_guess = [&](bool constant_velocity) {
    MatcherSettings settings;
    settings.constant_velocity = constant_velocity;
    ScanMatcher matcher(settings);
    std::mt19937 random(3);
    matcher.add_scan(ground.scan(hovering, downward_laser(), random));
    matcher.add_scan(ground.scan(hovering, downward_laser(), random), Pose2{0, 0.1, 0});
    const double after_guess = matcher.pose().y;
    EXPECT_NEAR(after_guess, 0.1, 0.02);  // the guess held: nothing on flat ground says otherwise
    for (int i = 0; i < 10; ++i) matcher.add_scan(ground.scan(hovering, downward_laser(), random));
    return matcher.pose().y - after_guess;
  };
  EXPECT_GT(std::abs(slide_after_the_guess(true)), 0.5);
  EXPECT_LT(std::abs(slide_after_the_guess(false)), 0.05);
}
