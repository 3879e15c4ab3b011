#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "scanbus/atmosphere.hpp"
#include "scanbus/mav_sim/flight.hpp"

using namespace scanbus;
using namespace scanbus::mav_sim;

TEST(GroundWorld, RaysHitTheGroundAndTheBoxes) {
  const GroundWorld world({{{4, 0}, 0, {0.6, 0.4, 0.3}}});
  const Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(world.cast({0, 0, 3}, down), 3.0, 1e-12);
  EXPECT_NEAR(world.cast({4, 0, 3}, down), 2.7, 1e-12);  // the box's top
  EXPECT_NEAR(world.cast({4.35, 0, 3}, down), 3.0, 1e-12);  // just past its end
  EXPECT_NEAR(world.cast({0, 0, 0.1}, Eigen::Vector3d::UnitX()), 3.7, 1e-12);  // its near side
  EXPECT_TRUE(std::isinf(world.cast({0, 0, 3}, Eigen::Vector3d::UnitZ())));
  EXPECT_NEAR(world.height_at({4.1, 0.1}), 0.3, 1e-9);
  EXPECT_NEAR(world.height_at({5, 0}), 0.0, 1e-9);
}

TEST(Flight, ScenarioOneGoesTenMetresAndBack) {
  FlightSettings settings;
  EXPECT_NEAR(scenario_state(settings, 0).position.x(), 0, 1e-9);
  EXPECT_NEAR(scenario_state(settings, 10).position.x(), 10, 1e-9);
  EXPECT_NEAR(scenario_state(settings, 20).position.x(), 0, 1e-9);
  // Accelerating forward at the start tilts the nose down (positive pitch about y).
  const Eigen::Vector3d forward = scenario_state(settings, 0.5).orientation * Eigen::Vector3d::UnitX();
  EXPECT_LT(forward.z(), 0);
}

TEST(Flight, RotationalHoverRollsByAboutTwelveDegrees) {
  FlightSettings settings;
  settings.scenario = 2;
  double largest = 0;
  for (double t = 0; t < 10; t += 0.05) {
    const Eigen::Vector3d side = scenario_state(settings, t).orientation * Eigen::Vector3d::UnitY();
    largest = std::max(largest, std::abs(std::asin(side.z())));
  }
  EXPECT_GT(largest * 180 / M_PI, 10);
  EXPECT_LT(largest * 180 / M_PI, 20);
}

TEST(Flight, SensorsAtTheirRatesAndTheLaserSeesTheGround) {
  FlightSettings settings;
  settings.duration = 2;
  const auto log = simulate_flight(settings);
  EXPECT_EQ(log.lasers.size(), 60u);
  EXPECT_EQ(log.imus.size(), 20u);
  EXPECT_EQ(log.fixes.size(), 20u);
  EXPECT_EQ(log.baros.size(), 20u);
  EXPECT_EQ(log.truths.size(), 200u);
  const auto& scan = log.lasers.front();
  EXPECT_EQ(scan.ranges.size(), 361u);  // 90 degrees in 0.25 degree steps
  // The middle ray points straight down from 10 cm under base_link: the height less 0.1 m.
  EXPECT_NEAR(scan.ranges[180], log.truths.front().position.z() - 0.1, 0.08);
  EXPECT_NEAR(altitude_at_pressure(log.baros.front().pressure), 34.0 + settings.height, 1.5);
  EXPECT_NEAR(log.fixes.front().latitude, settings.origin.x(), 1e-4);
}

TEST(Flight, ScenarioFourHasTheBoxesInTheScans) {
  FlightSettings settings;
  settings.scenario = 4;
  settings.duration = 12;
  const auto log = simulate_flight(settings);
  ASSERT_EQ(log.meta.at("boxes").size(), 3u);
  float nearest = INFINITY;
  for (const auto& scan : log.lasers)
    for (float range : scan.ranges) nearest = std::min(nearest, range);
  EXPECT_LT(nearest, settings.height - 0.1 - 0.3 + 0.5);  // a box top is nearer than the ground
}

TEST(Flight, SettingsOutOfRangeAreNamed) {
  FlightSettings settings;
  settings.scenario = 5;
  EXPECT_THROW(simulate_flight(settings), std::invalid_argument);
  settings.scenario = 1;
  settings.height = 100;
  try {
    simulate_flight(settings);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("height"), std::string::npos);
  }
}

TEST(MavLog, WritesAndReadsBack) {
  FlightSettings settings;
  settings.duration = 0.5;
  settings.scenario = 4;
  const auto log = simulate_flight(settings);
  const std::string path = ::testing::TempDir() + "/flight.mavlog";
  sensor_replay::write_mav_log(path, log);
  const auto back = sensor_replay::read_mav_log(path);
  ASSERT_EQ(back.lasers.size(), log.lasers.size());
  ASSERT_EQ(back.truths.size(), log.truths.size());
  EXPECT_EQ(back.meta.at("boxes"), log.meta.at("boxes"));
  EXPECT_NEAR(back.lasers[3].ranges[100], log.lasers[3].ranges[100], 5e-4);  // written to the millimetre
  EXPECT_NEAR(back.lasers[3].stamp, log.lasers[3].stamp, 1e-6);
  EXPECT_NEAR(back.baros[2].pressure, log.baros[2].pressure, 0.01);
  EXPECT_NEAR(back.truths[7].position.z(), log.truths[7].position.z(), 1e-6);
  EXPECT_NEAR(back.imus[1].orientation.angularDistance(log.imus[1].orientation), 0, 1e-7);
  EXPECT_NEAR(back.fixes[1].longitude, log.fixes[1].longitude, 1e-8);
}

TEST(MavLog, MalformedLinesAreNamed) {
  const std::string path = ::testing::TempDir() + "/bad.mavlog";
  std::ofstream(path) << "# x\nBARO 1.0 101000\nIMU 1.0 0 0 0\n";
  try {
    sensor_replay::read_mav_log(path);
    FAIL();
  } catch (const sensor_replay::MavLogError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.mavlog:3"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "BARO 1.0 -5\n";
  EXPECT_THROW(sensor_replay::read_mav_log(path), sensor_replay::MavLogError);
  std::ofstream(path) << "LASER 1.0 0 0.01 0.1 30 3 1.0 x 2.0\n";
  EXPECT_THROW(sensor_replay::read_mav_log(path), sensor_replay::MavLogError);
  EXPECT_THROW(sensor_replay::read_mav_log(path + ".missing"), sensor_replay::MavLogError);
}
