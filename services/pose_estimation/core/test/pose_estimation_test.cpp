#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "scanbus/atmosphere.hpp"
#include "scanbus/pose_estimation/height_fusion.hpp"
#include "scanbus/pose_estimation/laser_height.hpp"
#include "scanbus/pose_estimation/pose_estimator.hpp"

using namespace scanbus::pose_estimation;

TEST(LaserHeight, DownwardLaserSeesTheGroundComeCloser) {
  // The laser's x axis points down (a +90 degree pitch in the body): descending 0.2 m
  // moves the laser +0.2 m along its own x.
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();
  mount.translate(Eigen::Vector3d(0, 0, -0.1));
  mount.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  const Eigen::Quaterniond level = Eigen::Quaterniond::Identity();
  EXPECT_NEAR(height_change(0.2, 0, level, level, mount), -0.2, 1e-12);
  EXPECT_NEAR(height_change(0, 0.5, level, level, mount), 0, 1e-12);  // sideways
  // Rolled by 10 degrees: the laser's x leans, so part of a sideways move is height.
  const Eigen::Quaterniond rolled(Eigen::AngleAxisd(0.1745, Eigen::Vector3d::UnitX()));
  EXPECT_NEAR(height_change(0, 1.0, rolled, rolled, mount), std::sin(0.1745), 1e-3);
  // Rolling alone swings the laser on its 10 cm lever: the body did not move.
  const double swung = height_change(0, 0, level, rolled, mount);
  EXPECT_NEAR(swung, -(0.1 - 0.1 * std::cos(0.1745)), 1e-9);
}

namespace {

struct Track {
  std::vector<double> truth, baro, fused, integrated, sigma;
  std::vector<SettledHeight> settled;  // the heights as they left the window, less the truth
  uint64_t rejected = 0, baro_outliers = 0;
};

// A flight at 30 Hz with a height wave, flying back and forth along x at 0.5 m/s (24 s a
// pass): the barometer at 10 Hz with 0.3 m noise and a bias wandering 0.02 m/sqrt(s),
// scan-matcher changes with 3 mm noise and a 0.3 m jump now and then (failed matches).
// With ground: 61 returns across the flight, 3 m wide, 5 mm noise, on a ground of
// `slope` (dz/dx) with a 1 m high block from x = 8.2 m to the turn at 12 m when
// `over_block`; the matcher's changes then see the ground rise (its edges are the jumps).
// With GPS: altitudes at 10 Hz with `gps_sigma` reported, 2 cm jitter and a wander of
// that sigma changing over 30 s.
struct FlightPlan {
  int scans = 1800;
  unsigned seed = 3;
  bool over_block = false;
  double baro_jump = 0;  // m added to the barometer from 50 to 55 s (a gust, a door, a fault)
  bool ground = false;
  double slope = 0;
  double gps_sigma = 0;  // none when 0
};

double x_at(double t) {
  const double phase = std::fmod(t, 48.0);
  return phase < 24 ? 0.5 * phase : 0.5 * (48 - phase);
}

double true_height(double t) { return 3 + 0.4 * std::sin(t / 3); }

void take_settled(HeightFusion& fusion, Track& track, bool all = false) {
  for (SettledHeight node : fusion.take_settled(all)) {
    node.height -= true_height(node.stamp);
    track.settled.push_back(node);
  }
}

double ground_at(const FlightPlan& plan, double x) {
  return plan.slope * x + (plan.over_block && x >= 8.2 ? 1.0 : 0.0);
}

Track fly(const FusionSettings& settings, const FlightPlan& plan = {}) {
  std::mt19937 random(plan.seed), gps_random(plan.seed + 1000);  // GPS or not, the same other noise
  std::normal_distribution<double> gauss(0, 1);
  HeightFusion fusion(settings);
  Track track;
  double drift = 0, previous = 0, integrated = 0, wander = 0, previous_ground = 0;
  const bool ground = plan.ground || plan.over_block;
  for (int k = 0; k < plan.scans; ++k) {
    const double t = k / 30.0, h = true_height(t), x = x_at(t);
    if (k % 3 == 0) {
      drift += 0.02 * std::sqrt(0.1) * gauss(random);
      const double baro = h + drift + 0.3 * gauss(random) + (t >= 50 && t < 55 ? plan.baro_jump : 0.0);
      fusion.add_barometer(t, baro);
      track.baro.push_back(baro - h);
      if (k == 0) integrated = baro;
      if (plan.gps_sigma > 0) {
        wander += -wander * 0.1 / 30 + plan.gps_sigma * std::sqrt(2 * 0.1 / 30) * gauss(gps_random);
        fusion.add_gps(t, h + wander + 0.02 * gauss(gps_random), plan.gps_sigma);
      }
    }
    const double under = ground_at(plan, x);
    std::optional<double> change;
    if (k > 0) {
      const bool jumped = !plan.over_block && k % 350 == 100;
      change = h - previous - (ground ? under - previous_ground : 0.0) + 0.003 * gauss(random) + (jumped ? 0.3 : 0.0);
      integrated += *change;
    }
    previous = h;
    previous_ground = under;
    std::vector<GroundReturn> returns;
    if (ground)
      for (int i = 0; i <= 60; ++i) returns.push_back({{x, -1.5 + 0.05 * i}, h - under + 0.005 * gauss(random)});
    track.fused.push_back(fusion.add_node(t, change, returns) - h);
    track.sigma.push_back(fusion.height_sigma());
    track.integrated.push_back(integrated - h);
    take_settled(fusion, track);
  }
  take_settled(fusion, track, true);
  track.rejected = fusion.changes_rejected();
  track.baro_outliers = fusion.barometer_outliers();
  return track;
}

double rms(const std::vector<double>& errors) {
  double sum = 0;
  for (double e : errors) sum += e * e;
  return std::sqrt(sum / static_cast<double>(errors.size()));
}

}  // namespace

TEST(HeightFusion, BeatsBarometerAndIntegrationAndIgnoresFailedMatches) {
  const Track track = fly({});
  const double baro = rms(track.baro), integrated = rms(track.integrated), fused = rms(track.fused);
  std::printf("height RMSE: barometer %.3f m, integrated changes %.3f m, fused %.3f m\n", baro, integrated, fused);
  EXPECT_LT(fused, 0.5 * std::min(baro, integrated));
  EXPECT_LT(fused, 0.1);
  EXPECT_EQ(track.rejected, 5u);  // the five jumps, and nothing else
}

TEST(HeightFusion, ABarometerJumpIsCountedAndBarelyMovesTheHeight) {
  for (bool over_block : {false, true}) {
    const Track steady = fly({}, {2400, 3, over_block, 0.0});
    const Track jumped = fly({}, {2400, 3, over_block, 10.0});
    double worst = 0;  // the fused height's change from the jump, 50 to 60 s
    for (size_t k = 1500; k < 1800; ++k) worst = std::max(worst, std::abs(jumped.fused[k] - steady.fused[k]));
    std::printf("%s: a 10 m barometer jump for 5 s moved the fused height by at most %.3f m; %lu outliers\n",
                over_block ? "with ground" : "changes only", worst, static_cast<unsigned long>(jumped.baro_outliers));
    EXPECT_LT(worst, 0.1);
    EXPECT_EQ(jumped.baro_outliers, 50u);  // 5 s at 10 Hz
    EXPECT_EQ(steady.baro_outliers, 0u);
    EXPECT_LT(rms(jumped.fused), 0.1);
  }
}

TEST(HeightFusion, ABarometerShiftThatPersistsIsBelievedAfterTheGateTime) {
  FusionSettings settings;
  settings.initial_bias_sigma = 0.05;  // a barometer known to 5 cm: a 3 m step is 60 of its sigmas
  HeightFusion fusion(settings);
  double at_15s = 0;
  for (int k = 0; k < 400; ++k) {
    const double t = k * 0.1;
    fusion.add_barometer(t, t < 10 ? 5.0 : 8.0);  // a 3 m step at 10 s that stays
    fusion.add_node(t, std::nullopt);
    if (k == 150) at_15s = fusion.height();
  }
  EXPECT_NEAR(at_15s, 5.0, 0.05);          // within baro_gate_time: left out
  EXPECT_NEAR(fusion.height(), 8.0, 0.1);  // then believed
  // Without changes the height's own uncertainty grows while the barometer is left out, and
  // the gate widens with it: believed after 6 s here rather than baro_gate_time's 10.
  EXPECT_GE(fusion.barometer_outliers(), 30u);
}

TEST(HeightFusion, WithoutChangesItFollowsTheBarometer) {
  HeightFusion fusion;
  for (int k = 0; k < 300; ++k) {
    fusion.add_barometer(k * 0.1, 5.0);
    fusion.add_node(k * 0.1, std::nullopt);
  }
  EXPECT_NEAR(fusion.height(), 5.0, 0.05);
  EXPECT_LT(fusion.nodes_in_window(), 120u);  // the window slides
}

namespace {

// The map origin and a fix `east` m east of it, `up` m above it (small offsets: a flat
// approximation of WGS84 is within millimetres here).
constexpr double kLat = 52.5, kLon = 13.4, kAlt = 34.0;
constexpr double kMetresPerDegreeLat = 111260.0;  // WGS84 at 52.5 deg, within 0.1 %

PoseEstimatorSettings settings_at_origin() {
  PoseEstimatorSettings settings;
  settings.origin = {kLat, kLon, kAlt};
  settings.laser_in_body.translate(Eigen::Vector3d(0, 0, -0.1));
  settings.laser_in_body.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  return settings;
}

}  // namespace

TEST(PoseEstimator, AResultWaitsForImuAndGpsOnBothSides) {
  PoseEstimator estimator(settings_at_origin());
  estimator.add_pressure(0.0, scanbus::pressure_at_altitude(kAlt + 3));
  estimator.add_imu(0.0, Eigen::Quaterniond::Identity());
  estimator.add_fix(0.0, kLat, kLon, kAlt + 3, 0.5, 1.0);
  estimator.add_match(0.05, std::nullopt);
  EXPECT_TRUE(estimator.take_ready().empty());  // nothing after 0.05 s yet
  estimator.add_imu(0.1, Eigen::Quaterniond::Identity());
  EXPECT_TRUE(estimator.take_ready().empty());  // GPS still missing
  estimator.add_fix(0.1, kLat + 1 / kMetresPerDegreeLat, kLon, kAlt + 3, 0.5, 1.0);
  EXPECT_TRUE(estimator.take_ready().empty());  // and a pressure after it
  estimator.add_pressure(0.1, scanbus::pressure_at_altitude(kAlt + 3));
  const auto poses = estimator.take_ready();
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_TRUE(poses[0].has_attitude && poses[0].has_position);
  EXPECT_NEAR(poses[0].position.y(), 0.5, 0.002);  // half way to the fix 1 m north
  EXPECT_NEAR(poses[0].position.z(), 3.0, 0.01);   // the barometer's height above the origin
  EXPECT_DOUBLE_EQ(poses[0].position_sigma.x(), 0.5);
}

TEST(PoseEstimator, GoesAheadWithoutImuAfterMaxWait) {
  PoseEstimator estimator(settings_at_origin());
  estimator.add_pressure(0.0, scanbus::pressure_at_altitude(kAlt + 2));
  estimator.add_fix(0.0, kLat, kLon, kAlt + 2, 0.5, 1.0);
  estimator.add_match(0.1, Eigen::Vector2d(0.1, 0));
  EXPECT_TRUE(estimator.take_ready().empty());
  estimator.add_fix(0.7, kLat, kLon, kAlt + 2, 0.5, 1.0);  // 0.6 s later: the IMU is not coming
  const auto poses = estimator.take_ready();
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_FALSE(poses[0].has_attitude);
  EXPECT_FALSE(poses[0].match_used);  // no attitude, no height change
}

TEST(PoseEstimator, ScanMatcherChangesCarryTheHeightBetweenNoisyBarometerSamples) {
  // Climbing at 0.3 m/s, level: the laser (x down) moves along its -x. The barometer is
  // known to 5 cm at the start (the default allows for the decimetres of a take-off).
  PoseEstimatorSettings settings = settings_at_origin();
  settings.fusion.initial_bias_sigma = 0.05;
  PoseEstimator estimator(settings);
  std::mt19937 random(5);
  std::normal_distribution<double> gauss(0, 1);
  double worst = 0;
  for (int k = 0; k <= 600; ++k) {  // 20 s at 30 Hz
    const double t = k / 30.0, h = 3 + 0.3 * t;
    if (k % 3 == 0) {
      estimator.add_imu(t, Eigen::Quaterniond::Identity());
      estimator.add_fix(t, kLat, kLon, kAlt + h + 0.5 * gauss(random), 0.5, 1.0);
      estimator.add_pressure(t, scanbus::pressure_at_altitude(kAlt + h + 0.3 * gauss(random)));
    }
    if (k > 0) estimator.add_match(t, Eigen::Vector2d(-0.3 / 30 + 0.002 * gauss(random), 0));
    for (const auto& pose : estimator.take_ready()) {
      EXPECT_TRUE(pose.match_used || pose.stamp < 0.05);
      if (pose.stamp > 5) worst = std::max(worst, std::abs(pose.position.z() - (3 + 0.3 * pose.stamp)));
    }
  }
  std::printf("worst height error after 5 s: %.3f m (barometer noise 0.3 m)\n", worst);
  EXPECT_LT(worst, 0.15);
  EXPECT_GT(estimator.fusion().height_sigma(), 0.0);
  EXPECT_LT(estimator.fusion().height_sigma(), 0.15);
}

TEST(HeightFusion, GroundSeenAgainHoldsTheHeightOverABlock) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Track track = fly({}, {5400, seed, true});
    const double baro = rms(track.baro), integrated = rms(track.integrated), fused = rms(track.fused);
    double worst = 0;  // after the first pass, when only the barometer knows the ground
    for (size_t k = 720; k < track.fused.size(); ++k) worst = std::max(worst, std::abs(track.fused[k]));
    std::printf("seed %u: barometer %.3f m, integrated %.3f m, fused %.3f m, worst %.3f m\n", seed, baro, integrated,
                fused, worst);
    EXPECT_LT(fused, 0.5 * std::min(baro, integrated));
    EXPECT_LT(worst, 0.35);         // a block's edge never carries the height off by its 1 m
    EXPECT_EQ(track.rejected, 8u);  // the matcher's jumps at the 8 edges the flight crosses
  }
}

TEST(HeightFusion, EachHeightSettlesOnceCloserToTheTruth) {
  // Over the block and over the slope, where later scans see the same ground again.
  size_t within_sigma = 0, scored = 0;
  for (const bool over_block : {false, true}) {
    for (unsigned seed : {1u, 2u, 3u}) {
      FlightPlan plan{5400, seed, over_block};
      plan.ground = true;
      plan.slope = over_block ? 0.0 : 0.052;
      const Track track = fly({}, plan);
      ASSERT_EQ(track.settled.size(), track.fused.size());  // every node once, the window's at the end
      std::vector<double> errors;
      for (size_t k = 0; k < track.settled.size(); ++k) {
        EXPECT_DOUBLE_EQ(track.settled[k].stamp, k / 30.0);
        errors.push_back(track.settled[k].height);
        if (k < 30) continue;  // before the first solves
        within_sigma += std::abs(track.settled[k].height) <= track.settled[k].sigma;
        ++scored;
      }
      std::printf("%s, seed %u: fused height RMSE %.4f m as solved, %.4f m as settled\n",
                  over_block ? "block" : "slope", seed, rms(track.fused), rms(errors));
      EXPECT_LT(rms(errors), rms(track.fused));
    }
  }
  const double share = static_cast<double>(within_sigma) / static_cast<double>(scored);
  std::printf("settled errors within 1 sigma: %.1f %%\n", 100 * share);
  // Six correlated flights: a loose check, as above. It holds 89 %: the sigma is too wide
  // here (docs/performance.md: so it is over the simulated terrains).
  EXPECT_GT(share, 0.5);
  EXPECT_LT(share, 0.9);
}

TEST(HeightFusion, ReturnsThatCannotBePlacedAreLeftOut) {
  HeightFusion fusion;
  fusion.add_barometer(0, 3.0);
  std::vector<GroundReturn> wild;
  for (int i = 0; i < 20; ++i) {
    wild.push_back({{NAN, 0}, 3.0});
    wild.push_back({{1e300, -1e300}, 3.0});  // a fix gone wild: no cell index fits
    wild.push_back({{0.1, 0.1}, INFINITY});
  }
  EXPECT_NEAR(fusion.add_node(0, std::nullopt, wild), 3.0, 1e-9);
  EXPECT_EQ(fusion.ground_cells(), 0u);
}

TEST(HeightFusion, ASlopeUnderTheFlightIsNotTheMavSinking) {
  // 3 degrees up along the flight, 3 minutes back and forth: the laser alone cannot tell
  // the ground rising from the MAV sinking; the origin's ground and the ground seen again on
  // every pass can.
  size_t within_sigma = 0, scored = 0;
  for (unsigned seed : {1u, 2u, 3u}) {
    const Track track = fly({}, {5400, seed, false, 0.0, true, 0.052});
    const double baro = rms(track.baro), integrated = rms(track.integrated), fused = rms(track.fused);
    std::printf("seed %u: barometer %.3f m, integrated %.3f m, fused %.3f m\n", seed, baro, integrated, fused);
    EXPECT_LT(fused, 0.15);  // the barometer alone knows the slope (issue 19's standalone target)
    EXPECT_LT(fused, 0.5 * std::min(baro, integrated));
    for (size_t k = 30; k < track.fused.size(); ++k) {  // after the first solves
      within_sigma += std::abs(track.fused[k]) <= track.sigma[k];
      ++scored;
    }
  }
  // The height's printed sigma holds about two thirds of the errors (they are correlated
  // over a flight: three flights are a loose check).
  const double share = static_cast<double>(within_sigma) / static_cast<double>(scored);
  std::printf("errors within 1 sigma: %.1f %%\n", 100 * share);
  EXPECT_GT(share, 0.5);
  EXPECT_LT(share, 0.9);
}

TEST(HeightFusion, GpsAltitudeCountsAsMuchAsItsFixSays) {
  // Over a slope, without the origin's ground: an RTK fix (4 cm) carries the height, a
  // standalone one (4 m) does no harm.
  FusionSettings settings;
  settings.origin_on_ground = false;
  for (unsigned seed : {1u, 2u, 3u}) {
    const double none = rms(fly(settings, {5400, seed, false, 0.0, true, 0.052}).fused);
    const double rtk = rms(fly(settings, {5400, seed, false, 0.0, true, 0.052, 0.04}).fused);
    const double standalone = rms(fly(settings, {5400, seed, false, 0.0, true, 0.052, 4.0}).fused);
    std::printf("seed %u: fused without GPS %.3f m, with RTK %.3f m, with standalone %.3f m\n", seed, none, rtk,
                standalone);
    EXPECT_LT(rtk, 0.04);
    EXPECT_LT(rtk, 0.5 * none);
    EXPECT_LT(standalone, none + 0.01);
  }
}

TEST(HeightFusion, TheWholeFlightsFixesSetTheLevelNotTheFirstOnes) {
  // Slope seed 5, scenario III: the fix's error was +6 cm for the first half minute and about
  // nothing after; with its bias a random walk, the fused height kept the first fixes' +6 cm
  // for the whole flight (the ground map holds the level). As a Gauss-Markov wander, the later
  // fixes bring it back.
  FusionSettings settings;
  settings.origin_on_ground = false;
  HeightFusion fusion(settings);
  std::mt19937 random(5);
  std::normal_distribution<double> gauss(0, 1);
  double error = 0;
  for (int k = 0; k < 30 * 180; ++k) {
    const double t = k / 30.0, h = 3.0;
    if (k % 3 == 0) {
      fusion.add_barometer(t, h + 0.3 + 0.3 * gauss(random));
      fusion.add_gps(t, h + (t < 30 ? 0.06 : 0.0) + 0.02 * gauss(random), 0.036);
    }
    std::vector<GroundReturn> returns;
    for (int i = 0; i <= 60; ++i) returns.push_back({{-1.5 + 0.05 * i, 0.0}, h + 0.005 * gauss(random)});
    error = fusion.add_node(t, k > 0 ? std::optional<double>(0.003 * gauss(random)) : std::nullopt, returns) - h;
  }
  std::printf("height error after 180 s: %+.3f m (sigma %.3f m)\n", error, fusion.height_sigma());
  EXPECT_LT(std::abs(error), 0.025);  // a random walk: +0.06
}

TEST(HeightFusion, TheFirstHeightsFollowAnRtkFixNotTheBarometerAlone) {
  // Scenario IV seed 8 at 30.1 Hz: the first two scans came out 0.27 m high (the barometer's
  // take-off offset), stood out of the ground as a 4 m "box" and took box P to 49.6 %.
  HeightFusion fusion;
  fusion.add_barometer(0, 3.27);
  fusion.add_gps(0, 3.00, 0.02);
  EXPECT_NEAR(fusion.add_node(0, std::nullopt), 3.0, 0.03);
  EXPECT_LT(fusion.height_sigma(), 0.05);
  EXPECT_NEAR(fusion.add_node(0.033, 0.0), 3.0, 0.03);  // propagated from the first until the next solve
}

TEST(HeightFusion, AFirstNodeWithoutAnAltitudeKeepsABoundedSigma) {
  HeightFusion fusion;
  fusion.add_barometer(0.05, 3.27);  // the first pressure just after the first scan
  fusion.add_node(0, std::nullopt);
  EXPECT_LT(fusion.height_sigma(), 1.0);
}

TEST(PoseEstimator, OnceScansComeAMatchWaitsForItsOwn) {
  PoseEstimator estimator(settings_at_origin());
  for (double t : {0.0, 0.1}) {
    estimator.add_pressure(t, scanbus::pressure_at_altitude(kAlt + 3));
    estimator.add_imu(t, Eigen::Quaterniond::Identity());
    estimator.add_fix(t, kLat, kLon, kAlt + 3, 0.5, 1.0);
  }
  std::vector<float> flat;
  for (int i = 0; i <= 360; ++i) flat.push_back(static_cast<float>(2.9 / std::cos((i - 180) * 0.25 * M_PI / 180)));
  estimator.add_scan({0.0, -M_PI / 4, 0.25 * M_PI / 180, 0.1, 30, flat});
  estimator.add_match(0.0, std::nullopt);
  estimator.add_match(0.05, std::nullopt);
  auto poses = estimator.take_ready();
  ASSERT_EQ(poses.size(), 1u);  // the second waits for its scan
  ASSERT_TRUE(poses[0].clearance.has_value());
  EXPECT_NEAR(*poses[0].clearance, 3.0, 1e-3);
  estimator.add_scan({0.05, -M_PI / 4, 0.25 * M_PI / 180, 0.1, 30, std::vector<float>(361, NAN)});  // no returns
  poses = estimator.take_ready();
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_FALSE(poses[0].clearance.has_value());
}

// The same samples arriving in another order (the barometer's late, as on a loaded machine
// where the scan matcher's results overtake it) give the same heights.
TEST(PoseEstimator, HeightsDoNotDependOnTheOrderSamplesArrive) {
  const auto run = [](bool pressures_late) {
    PoseEstimator estimator(settings_at_origin());
    std::vector<EstimatedPose> poses;
    const auto pressure = [](int i) { return scanbus::pressure_at_altitude(kAlt + 3 + 0.3 * std::sin(i * 0.7)); };
    for (int i = 0; i < 200; ++i) {
      const double t = 0.05 * i;
      estimator.add_imu(t, Eigen::Quaterniond::Identity());
      estimator.add_fix(t, kLat, kLon, kAlt + 3, 0.5, 1.0);
      if (!pressures_late) estimator.add_pressure(t, pressure(i));
      estimator.add_match(t, Eigen::Vector2d(0.01 * std::cos(i * 0.3), 0));
      // Late: each pressure comes two matches after its own match.
      if (pressures_late && i >= 2) estimator.add_pressure(0.05 * (i - 2), pressure(i - 2));
      for (const auto& pose : estimator.take_ready()) poses.push_back(pose);
    }
    return poses;
  };
  const auto in_order = run(false), late = run(true);
  ASSERT_GE(late.size(), 190u);
  for (size_t i = 0; i < late.size(); ++i) {
    EXPECT_DOUBLE_EQ(late[i].stamp, in_order[i].stamp);
    EXPECT_DOUBLE_EQ(late[i].position.z(), in_order[i].position.z()) << "pose " << i;
  }
}

// The settled height replaces the first solve unless the window widened its sigma more than
// twice (the robust losses discounting the node's own cells), or the sigma is unknown.
TEST(PoseEstimator, AWidenedSettledSigmaKeepsTheFirstSolve) {
  EstimatedPose first;
  first.position = {1, 2, 3.0};
  first.position_sigma = {0.01, 0.01, 0.02};
  const auto narrower = settled_pose(first, {0, 3.01, 0.015});
  ASSERT_TRUE(narrower.has_value());
  EXPECT_EQ(narrower->position, Eigen::Vector3d(1, 2, 3.01));
  EXPECT_EQ(narrower->position_sigma, Eigen::Vector3d(0.01, 0.01, 0.015));
  EXPECT_TRUE(settled_pose(first, {0, 3.05, 0.04}).has_value());  // twice: still settled
  EXPECT_FALSE(settled_pose(first, {0, 3.29, 0.30}).has_value());
  EXPECT_FALSE(settled_pose(first, {0, 3.0, NAN}).has_value());
}

// Each pose settles once, in order, where it was placed but for its height and that
// height's sigma; the input's end settles those still in the window, and a later input
// does not settle them again.
TEST(PoseEstimator, EachPoseSettlesOnceAfterTheWindow) {
  PoseEstimator estimator(settings_at_origin());
  std::vector<EstimatedPose> ready, settled;
  const auto fly = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      const double t = 0.05 * i;
      estimator.add_imu(t, Eigen::Quaterniond::Identity());
      estimator.add_fix(t, kLat, kLon, kAlt + 3 + 0.02 * std::sin(i), 0.5, 0.05);
      estimator.add_pressure(t, scanbus::pressure_at_altitude(kAlt + 3 + 0.3 * std::sin(i * 0.7)));
      estimator.add_match(t, Eigen::Vector2d(0.01 * std::cos(i * 0.3), 0));
      for (const auto& pose : estimator.take_ready()) ready.push_back(pose);
      for (const auto& pose : estimator.take_settled()) settled.push_back(pose);
    }
  };
  fly(0, 200);  // 10 s
  const FusionSettings fusion;
  ASSERT_FALSE(settled.empty());
  EXPECT_LE(settled.back().stamp, ready.back().stamp - fusion.window);  // only what left the window
  for (const auto& pose : estimator.take_ready(true)) ready.push_back(pose);
  for (const auto& pose : estimator.take_settled(true)) settled.push_back(pose);
  ASSERT_EQ(settled.size(), ready.size());
  fly(200, 300);  // the input goes on after a pause
  for (const auto& pose : estimator.take_ready(true)) ready.push_back(pose);
  for (const auto& pose : estimator.take_settled(true)) settled.push_back(pose);
  ASSERT_EQ(settled.size(), ready.size());
  size_t moved = 0, narrower = 0;  // solved again with the samples after them
  for (size_t i = 0; i < settled.size(); ++i) {
    moved += settled[i].position.z() != ready[i].position.z();
    narrower += settled[i].position_sigma.z() < ready[i].position_sigma.z();
    EXPECT_DOUBLE_EQ(settled[i].stamp, ready[i].stamp);
    EXPECT_EQ(settled[i].position.head<2>(), ready[i].position.head<2>());
    EXPECT_TRUE(settled[i].orientation.isApprox(ready[i].orientation, 0));
    EXPECT_GT(settled[i].position_sigma.z(), 0);
    EXPECT_LT(settled[i].position_sigma.z(), 0.3);
  }
  std::printf("%zu of %zu heights moved as they settled, %zu with a narrower sigma\n", moved, settled.size(), narrower);
  EXPECT_GT(moved, settled.size() * 9 / 10);
  EXPECT_GT(narrower, settled.size() * 9 / 10);
}
