#include "scanbus/pose_estimation/scan_plane_calibration.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "scanbus/config.hpp"
#include "scanbus/pose_estimation/pose_estimator.hpp"
#include "scanbus/transforms/transform_buffer.hpp"
#include "scanbus/units.hpp"

using namespace scanbus;
using namespace scanbus::pose_estimation;

namespace {

// A MAV hovering 3 m over the plane z = slope . (x, y), drifting a few centimetres and turning
// once in 18 s; its laser mounted as drawn (looking down, scan plane across the body) but
// turned `turn` in its scan plane and leaning 0.3 degrees about its other axes. Ranges carry
// `noise` (m, one sigma), IMU attitudes come at 10 Hz.
struct HoverTurn {
  double turns = 5.05, turn = 0.5 * kDegree, noise = 0.02;
  Eigen::Vector2d slope{0.04, -0.03};
  unsigned seed = 1;

  Eigen::Isometry3d drawn() const { return transforms::from_xyz_rpy({0, 0, -0.1}, {0, M_PI / 2, 0}); }

  void fly(std::vector<sensor::LaserScan>& scans, std::vector<AttitudeSample>& attitudes) const {
    std::mt19937 random(seed);
    std::normal_distribution<double> gauss(0, 1);
    const Eigen::Isometry3d mount =
        turned_in_scan_plane(drawn(), turn) * Eigen::AngleAxisd(0.3 * kDegree, Eigen::Vector3d(1, 1, 0).normalized());
    const double duration = turns * 18;
    for (int i = 0; i * (1 / 30.0) < duration; ++i) {
      const double t = i / 30.0;
      const Eigen::Quaterniond body(Eigen::AngleAxisd(2 * M_PI * t / 18, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(0.01 * std::sin(t), Eigen::Vector3d::UnitX()));
      if (i % 3 == 0) attitudes.push_back({t, body});
      const Eigen::Isometry3d laser =
          Eigen::Translation3d(0.05 * std::sin(t / 3), 0.05 * std::cos(t / 5), 3) * body * mount;
      sensor::LaserScan scan;
      scan.stamp = t, scan.angle_min = -M_PI / 4, scan.angle_increment = 0.25 * kDegree, scan.range_max = 30;
      for (int ray = 0; ray <= 360; ++ray) {
        const double angle = scan.angle(ray);
        const Eigen::Vector3d d = laser.linear() * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0);
        const Eigen::Vector3d o = laser.translation();
        const double range = (slope.dot(o.head<2>()) - o.z()) / (d.z() - slope.dot(d.head<2>()));
        scan.ranges.push_back(static_cast<float>(range + noise * gauss(random)));
      }
      scans.push_back(std::move(scan));
    }
  }

  ScanPlaneCalibration calibrate(const ScanPlaneCalibrationSettings& settings = {}) const {
    std::vector<sensor::LaserScan> scans;
    std::vector<AttitudeSample> attitudes;
    fly(scans, attitudes);
    return calibrate_scan_plane(scans, attitudes, drawn(), settings);
  }
};

}  // namespace

TEST(ScanPlaneCalibration, FindsTheLasersTurnInItsScanPlaneOverASlope) {
  for (double turn : {0.5, -0.8, 0.0}) {
    HoverTurn flight;
    flight.turn = turn * kDegree;
    const ScanPlaneCalibration result = flight.calibrate();
    ASSERT_TRUE(result.ok) << result.status;
    EXPECT_NEAR(result.rotation / kDegree, turn, 0.02) << result.status;
    EXPECT_EQ(result.turns.size(), 5u);
    EXPECT_GT(result.sigma, 0);
    EXPECT_LT(result.sigma / kDegree, 0.05);
    EXPECT_NEAR(result.line_residual, 0.02, 0.005);  // the range noise: the slope is no unevenness
  }
}

TEST(ScanPlaneCalibration, ItsSigmaHoldsTheErrorOverSeeds) {
  // Without a sloped ground's drift or relief, the error is the noise the turns' spread sees.
  int within = 0;
  constexpr int kSeeds = 30;
  for (unsigned seed = 1; seed <= kSeeds; ++seed) {
    HoverTurn flight;
    // A noisy laser, so that the noise, not the model, is tested; turned little, as noise along
    // a ray fanned off the vertical biases a line's slope by about its variance times the turn.
    flight.seed = seed, flight.noise = 0.1, flight.turn = 0.1 * kDegree;
    ScanPlaneCalibrationSettings settings;
    settings.max_line_residual = 1;
    const ScanPlaneCalibration result = flight.calibrate(settings);
    ASSERT_TRUE(result.ok) << result.status;
    within += std::abs(result.rotation - flight.turn) <= result.sigma;
  }
  EXPECT_GE(within, 0.5 * kSeeds);
  EXPECT_LE(within, 0.85 * kSeeds);
}

TEST(ScanPlaneCalibration, RefusesAFlightThatDoesNotTurnEnough) {
  HoverTurn flight;
  flight.turns = 2.5;
  const ScanPlaneCalibration result = flight.calibrate();
  EXPECT_FALSE(result.ok);
  EXPECT_TRUE(std::isnan(result.rotation));
  EXPECT_NE(result.status.find("3 whole turns are needed"), std::string::npos) << result.status;
  ScanPlaneCalibrationSettings one_turn;
  one_turn.min_turns = 1;  // no spread to take a sigma from
  EXPECT_NE(flight.calibrate(one_turn).status.find("min_turns is 1, at least 2"), std::string::npos);
}

TEST(ScanPlaneCalibration, RefusesATurnWithHeadingsUnseen) {
  HoverTurn flight;
  std::vector<sensor::LaserScan> scans;
  std::vector<AttitudeSample> attitudes;
  flight.fly(scans, attitudes);
  // No IMU from 20 to 23 s: the second turn's scans at 40-100 degrees of heading have no attitude.
  attitudes.erase(std::remove_if(attitudes.begin(), attitudes.end(),
                                 [](const AttitudeSample& a) { return a.stamp > 20 && a.stamp < 23; }),
                  attitudes.end());
  const ScanPlaneCalibration result = calibrate_scan_plane(scans, attitudes, flight.drawn());
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.status.find("whole turn 2 has no scan at headings 60 to 90 degrees"), std::string::npos)
      << result.status;
}

TEST(ScanPlaneCalibration, RefusesUnevenGround) {
  HoverTurn flight;
  flight.noise = 0.1;  // stands for ground that is rough by a decimetre
  const ScanPlaneCalibration result = flight.calibrate();
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.status.find("not level and even"), std::string::npos) << result.status;
}

TEST(ScanPlaneCalibration, RefusesScansWithoutAttitudes) {
  HoverTurn flight;
  std::vector<sensor::LaserScan> scans;
  std::vector<AttitudeSample> attitudes;
  flight.fly(scans, attitudes);
  for (auto& attitude : attitudes) attitude.stamp += 1000;  // another clock
  const ScanPlaneCalibration result = calibrate_scan_plane(scans, attitudes, flight.drawn());
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.status.find("IMU attitudes"), std::string::npos) << result.status;
}

TEST(ScanPlaneCalibration, TheConfiguredRotationTurnsTheMount) {
  const auto settings_of = [](const std::string& mount) {
    return pose_estimator_settings_from_config(
        Config::parse("pose_estimation: {origin: [47.0, 8.0, 400.0], laser_mount: " + mount + "}", "pose.yaml")
            .section("pose_estimation"));
  };
  const Eigen::Isometry3d drawn = settings_of("{rpy: [0, 90, 0]}").laser_in_body;
  const Eigen::Isometry3d turned = settings_of("{rpy: [0, 90, 0], scan_plane_rotation: 0.7}").laser_in_body;
  EXPECT_TRUE(turned.isApprox(turned_in_scan_plane(drawn, 0.7 * kDegree)));
  // The ray straight down in the laser's x leans 0.7 degrees across the body, within the scan plane.
  const Eigen::Vector3d down = turned.linear() * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(down.y(), std::sin(0.7 * kDegree), 1e-9);
  EXPECT_NEAR(down.x(), 0, 1e-9);
  EXPECT_THROW(settings_of("{scan_plane_rotation: 45}"), ConfigError);
}
