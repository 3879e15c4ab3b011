#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <set>

#include "scanbus/atmosphere.hpp"
#include "scanbus/config.hpp"
#include "scanbus/mav_sim/flight.hpp"

using namespace scanbus;
using namespace scanbus::mav_sim;

TEST(GroundWorld, RaysHitTheGroundAndTheBoxes) {
  const GroundWorld world({{{4, 0}, 0, {0.6, 0.4, 0.3}}});
  const Eigen::Vector3d down = -Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(world.cast({0, 0, 3}, down), 3.0, 1e-12);
  EXPECT_NEAR(world.cast({4, 0, 3}, down), 2.7, 1e-12);                        // the box's top
  EXPECT_NEAR(world.cast({4.35, 0, 3}, down), 3.0, 1e-12);                     // just past its end
  EXPECT_NEAR(world.cast({0, 0, 0.1}, Eigen::Vector3d::UnitX()), 3.7, 1e-12);  // its near side
  EXPECT_TRUE(std::isinf(world.cast({0, 0, 3}, Eigen::Vector3d::UnitZ())));
  EXPECT_NEAR(world.height_at({4.1, 0.1}), 0.3, 1e-9);
  EXPECT_NEAR(world.height_at({5, 0}), 0.0, 1e-9);
}

TEST(Terrain, FeaturesAddUp) {
  Terrain terrain;
  terrain.slope = {0.05, -0.02};
  terrain.mounds = {{{10, 0}, 2, 0.4}, {{-10, 0}, 1, -0.3}};  // a mound and a ditch
  terrain.steps = {{{0, 5}, M_PI / 2, 0.2, 0.02}};            // the ground 0.2 m higher north of y = 5
  const TerrainSurface surface(terrain);
  EXPECT_NEAR(surface.height_at({0, 0}), 0, 1e-12);
  EXPECT_NEAR(surface.height_at({10, 0}), 0.5 + 0.4, 1e-12);
  EXPECT_NEAR(surface.height_at({11, 0}), 0.55 + 0.2, 1e-12);  // half way out: half the height
  EXPECT_NEAR(surface.height_at({-10, 0}), -0.5 - 0.3, 1e-12);
  EXPECT_NEAR(surface.height_at({0, 4.9}), -0.098, 1e-12);
  EXPECT_NEAR(surface.height_at({0, 5.1}), -0.102 + 0.2, 1e-12);
  EXPECT_TRUE(Terrain{}.flat());
  EXPECT_FALSE(terrain.flat());
}

// A step whose high side covers the origin, and a mound over it: the ground at the origin,
// where the flight starts, stays at z = 0 and the rest keeps its shape around it.
TEST(Terrain, TheOriginIsOnTheGround) {
  Terrain terrain;
  terrain.steps = {{{2.6, 0}, M_PI, 0.15, 0.05}};  // the ground 0.15 m higher west of x = 2.6
  terrain.mounds = {{{0, 0}, 1, 0.2}};
  const TerrainSurface surface(terrain);
  EXPECT_NEAR(surface.height_at({0, 0}), 0, 1e-12);
  EXPECT_NEAR(surface.height_at({2, 0}), -0.2, 1e-12);
  EXPECT_NEAR(surface.height_at({3, 0}), -0.35, 1e-12);
  terrain.roughness = 0.02;  // the rough ground the origin was taken on stays
  EXPECT_GT(std::abs(TerrainSurface(terrain).height_at({0, 0})), 1e-6);
}

TEST(Terrain, RoughGroundHasTheRmsAskedFor) {
  Terrain terrain;
  terrain.roughness = 0.03;
  const TerrainSurface surface(terrain);
  double sum = 0, squares = 0;
  int n = 0;
  for (double x = -10; x < 10; x += 0.03)
    for (double y = -10; y < 10; y += 0.03, ++n) {
      const double z = surface.height_at({x, y});
      sum += z, squares += z * z;
    }
  EXPECT_NEAR(std::sqrt(squares / n), 0.03, 0.003);
  EXPECT_NEAR(sum / n, 0, 0.003);
}

// Rays from the air meet the surface where it is (within 0.1 mm) and never pass through it first.
TEST(Terrain, RaysStopAtTheFirstSurface) {
  Terrain terrain;
  terrain.slope = {0.05, 0.03};
  terrain.mounds = {{{3, 1}, 1.5, 0.5}};
  terrain.steps = {{{5, 0}, 0.3, -0.3, 0.05}};
  terrain.roughness = 0.03;
  const TerrainSurface surface(terrain);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> place(-2, 8), tilt(-1.2, 1.2), turn(-M_PI, M_PI);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d origin(place(random), place(random) / 2, 3.5);
    const double a = tilt(random), b = turn(random);
    const Eigen::Vector3d direction(std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), -std::cos(a));
    const double range = surface.cast(origin, direction);
    ASSERT_TRUE(std::isfinite(range));
    const Eigen::Vector3d hit = origin + range * direction;
    EXPECT_NEAR(hit.z(), surface.height_at(hit.head<2>()), 1e-4);
    for (double t = 0; t < range - 0.005; t += 0.005) {
      const Eigen::Vector3d p = origin + t * direction;
      ASSERT_GT(p.z(), surface.height_at(p.head<2>())) << "ray " << i << " passed through the ground at " << t << " m";
    }
  }
  EXPECT_TRUE(std::isinf(surface.cast({0, 0, 3}, Eigen::Vector3d::UnitZ())));
}

TEST(GroundWorld, BoxesStandOnTheTerrain) {
  Terrain terrain;
  terrain.slope = {0.1, 0};
  const GroundWorld world({{{4, 0}, 0, {0.6, 0.4, 0.3}}}, terrain);
  EXPECT_NEAR(world.height_at({4, 0}), 0.4 + 0.3, 1e-9);  // the box's top over its centre's ground
  EXPECT_NEAR(world.height_at({6, 0}), 0.6, 1e-9);        // the slope beside it
  EXPECT_NEAR(world.cast({4, 0, 3}, -Eigen::Vector3d::UnitZ()), 3 - 0.7, 1e-9);
}

TEST(Flight, TheLaserSeesTheTerrainAndTheMavKeepsItsAltitude) {
  FlightSettings settings;
  settings.duration = 12;
  settings.terrain.slope = {0.05, 0};  // rising 0.5 m over the 10 m of scenario I
  settings.laser.noise = 0;
  const auto log = simulate_flight(settings);
  for (size_t i = 0; i < log.lasers.size(); i += 30) {
    const double t = log.lasers[i].stamp - settings.start_stamp;
    const BodyState truth = scenario_state(settings, t);
    // The middle ray looks about straight down (the body tilts by a degree or two).
    EXPECT_NEAR(log.lasers[i].ranges[180], truth.position.z() - 0.1 - 0.05 * truth.position.x(), 0.03) << "t " << t;
  }
  settings.terrain.mounds = {{{5, 0}, 2, 3.0}};  // a hill the MAV would fly into
  try {
    simulate_flight(settings);
    FAIL() << "a terrain reaching the MAV was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("terrain rises"), std::string::npos) << error.what();
  }
}

TEST(GroundWorld, EdgesAreNotScored) {
  Terrain terrain;
  terrain.steps = {{{8, 0}, 0, 0.2, 0.02}};
  const GroundWorld world({{{4, 0}, 0, {0.6, 0.4, 0.3}}}, terrain);
  EXPECT_NEAR(*world.scored_height({4, 0}, 0.1), 0.3, 1e-9);      // the box's top, 0.2 m inside
  EXPECT_FALSE(world.scored_height({4.25, 0}, 0.1).has_value());  // 5 cm inside its end
  EXPECT_FALSE(world.scored_height({4.35, 0}, 0.1).has_value());  // 5 cm past it
  EXPECT_NEAR(*world.scored_height({4.45, 0}, 0.1), 0.0, 1e-9);
  EXPECT_FALSE(world.scored_height({8.05, 3}, 0.1).has_value());  // on the step's ramp side
  EXPECT_NEAR(*world.scored_height({8.2, 3}, 0.1), 0.2, 1e-9);
}

// A block across a step down stands on both levels: its top is its height above the ground at
// its centre, and a ray aimed under its low end hits its side, not the ground beneath it.
TEST(GroundWorld, ABoxReachesDownToTheLowestGroundUnderIt) {
  Terrain terrain;
  terrain.steps = {{{5, 0}, 0, -0.3, 0.02}};  // the ground 0.3 m lower beyond x = 5
  const GroundWorld world({{{4, 0}, 0, {4, 1, 1.0}}}, terrain);
  EXPECT_NEAR(world.height_at({3, 0}), 1.0, 1e-9);
  EXPECT_NEAR(world.height_at({5.5, 0}), 1.0, 1e-9);                             // the same top over the lower ground
  EXPECT_NEAR(world.cast({8, 0, -0.15}, -Eigen::Vector3d::UnitX()), 2.0, 1e-9);  // its side at x = 6
  // A 2 x 0.2 m box turned by 30 degrees on a slope rising towards (1, 1): its lowest corner,
  // local (-1, -0.1), lies 1.366 + 0.037 m down the slope's axis (turned by -30 degrees it
  // would be 0.366 + 0.137 m).
  Terrain slope;
  slope.slope = {0.1, 0.1};
  const GroundWorld turned({{{0, 0}, M_PI / 6, {2, 0.2, 1.0}}}, slope);
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  EXPECT_NEAR(turned.boxes()[0].bottom, -0.1 * ((c + s) + 0.1 * (c - s)), 1e-9);
  EXPECT_THROW(GroundWorld({{{0, 0}, 0, {0, 0.2, 1.0}}}, slope), std::invalid_argument);
}

// A simulated log carries its ground (META scenario, boxes, terrain_*): the same world comes
// back from the text file, and a log that does not say has none.
TEST(Flight, TheLogCarriesItsTrueGround) {
  FlightSettings settings;
  settings.scenario = 4;
  settings.duration = 1;
  settings.terrain.slope = {0.03, -0.01};
  settings.terrain.mounds = {{{2, 1}, 1.5, -0.2}};
  settings.terrain.steps = {{{9, 0}, 0.5, 0.1, 0.04}};
  settings.terrain.roughness = 0.02;
  const std::string path = ::testing::TempDir() + "/terrain_flight.mavlog";
  sensor_replay::write_mav_log(path, simulate_flight(settings));
  const auto log = sensor_replay::read_mav_log(path);
  const auto world = world_of_log(log);
  ASSERT_TRUE(world.has_value());
  const GroundWorld truth = scenario_world(settings);
  for (double x = -2; x < 12; x += 0.37)
    for (double y = -3; y < 3; y += 0.41)
      EXPECT_NEAR(world->height_at({x, y}), truth.height_at({x, y}), 1e-6) << x << " " << y;
  auto unknown = log;
  unknown.meta.erase("scenario");
  EXPECT_FALSE(world_of_log(unknown).has_value());
  auto broken = log;
  broken.meta["terrain_mounds"].pop_back();
  EXPECT_THROW(world_of_log(broken), sensor_replay::MavLogError);
  for (const double size : {1e6, 0.0, double(NAN)}) {  // a box the world could not be built around
    for (int side = 0; side < 3; ++side) {
      auto bad = log;
      bad.meta["boxes"] = {0.6, 0.4, 0.3};
      bad.meta["boxes"][side] = size;
      EXPECT_THROW(world_of_log(bad), sensor_replay::MavLogError) << size << " as side " << side;
    }
  }
}

TEST(Terrain, FromYaml) {
  const Config config = Config::parse(R"(terrain:
  slope: [0.05, 0]
  mounds: [{centre: [5, 0], radius: 3, height: 0.4}, {centre: [-4, 2], radius: 1, height: -0.3}]
  steps: [{at: [7, 0], direction: 90, height: 0.2, width: 0.05}]
  roughness: 0.02
  roughness_wavelength: 0.8
  seed: 7
)",
                                      "terrain.yaml");
  const Terrain terrain = terrain_from_config(config.section("terrain"));
  config.check_all_read();
  EXPECT_EQ(terrain.mounds.size(), 2u);
  EXPECT_DOUBLE_EQ(terrain.mounds[1].height, -0.3);
  EXPECT_NEAR(terrain.steps[0].direction, M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(terrain.roughness_wavelength, 0.8);
  EXPECT_EQ(terrain.roughness_seed, 7u);
  auto refused = [](const std::string& text) {
    try {
      const Config bad = Config::parse(text, "bad.yaml");
      terrain_from_config(bad.section("terrain"));
      bad.check_all_read();
    } catch (const ConfigError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_NE(refused("terrain: {slope: [2, 0]}").find("slope"), std::string::npos);
  EXPECT_NE(refused("terrain: {mounds: [{centre: [0, 0], radius: 0, height: 1}]}").find("radius"), std::string::npos);
  EXPECT_NE(refused("terrain: {roughnes: 0.02}").find("roughnes"), std::string::npos);
  std::string many = "terrain: {steps: [";
  for (int i = 0; i < 101; ++i)
    many += std::string(i ? ", " : "") + "{at: [0, 0], direction: 0, height: 0.1, width: 0.1}";
  EXPECT_NE(refused(many + "]}").find("more than 100"), std::string::npos);
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

namespace {

// Altitude error of each barometer sample and vertical error of each fix against the truth.
struct SensorErrors {
  std::vector<double> barometer, gps_vertical;
};
SensorErrors sensor_errors(const FlightSettings& settings, const sensor_replay::MavLog& log) {
  SensorErrors errors;
  for (const auto& baro : log.baros) {
    const double t = baro.stamp - settings.start_stamp;
    errors.barometer.push_back(altitude_at_pressure(baro.pressure) - settings.origin.z() -
                               scenario_state(settings, t).position.z());
  }
  for (const auto& fix : log.fixes) {
    const double t = fix.stamp - settings.start_stamp;
    errors.gps_vertical.push_back(fix.altitude - settings.origin.z() - scenario_state(settings, t).position.z());
  }
  return errors;
}

}  // namespace

// The same draws at every scale: no errors at 0, twice the errors at 2 (the x0.5 / x2 sweeps
// change the size of the errors, not which ones).
TEST(Flight, EveryErrorScalesWithTheNoiseScale) {
  FlightSettings settings;
  settings.duration = 20;
  settings.laser.rate = 1;
  SensorErrors at[3];
  for (int scale : {0, 1, 2}) {
    settings.noise_scale = scale;
    at[scale] = sensor_errors(settings, simulate_flight(settings));
  }
  for (size_t i = 0; i < at[1].barometer.size(); ++i) {
    EXPECT_NEAR(at[0].barometer[i], 0, 1e-3);
    EXPECT_NEAR(at[2].barometer[i], 2 * at[1].barometer[i], 2e-3);
  }
  for (size_t i = 0; i < at[1].gps_vertical.size(); ++i) {
    EXPECT_NEAR(at[0].gps_vertical[i], 0, 1e-4);  // the altitude is not quite the local up
    EXPECT_NEAR(at[2].gps_vertical[i], 2 * at[1].gps_vertical[i], 1e-4);
  }
  settings.noise_scale = 11;
  EXPECT_THROW(simulate_flight(settings), std::invalid_argument);
}

// A receiver in each mode reports the sigma its vertical errors have (RMS over 8 ten-minute
// flights within 0.7-1.3 of the reported sigma), from centimetres (RTK fixed) to metres.
TEST(Flight, TheGpsReportsTheSigmaItsErrorsHave) {
  const std::pair<GpsMode, std::pair<double, double>> modes[] = {
      {GpsMode::rtk_fixed, {0.02, 0.06}}, {GpsMode::rtk_float, {0.3, 0.8}}, {GpsMode::standalone, {2.0, 6.0}}};
  for (const auto& [mode, reported_range] : modes) {
    double squares = 0, reported = 0;
    size_t n = 0;
    for (unsigned seed = 1; seed <= 8; ++seed) {
      FlightSettings settings;
      settings.scenario = 2;
      settings.duration = 600;
      settings.laser.rate = 0.1;
      settings.seed = seed;
      settings.noise = with_gps(settings.noise, mode);
      const auto log = simulate_flight(settings);
      for (double e : sensor_errors(settings, log).gps_vertical) squares += e * e, ++n;
      reported = log.fixes.front().vertical_sigma;
    }
    const double rms = std::sqrt(squares / static_cast<double>(n));
    std::printf("GPS mode %d: vertical error RMS %.3f m, reported sigma %.3f m\n", static_cast<int>(mode), rms,
                reported);
    EXPECT_GT(reported, reported_range.first);
    EXPECT_LT(reported, reported_range.second);
    EXPECT_GT(rms / reported, 0.7);
    EXPECT_LT(rms / reported, 1.3);
  }
}

// The survey patterns: the lawnmower visits its four lanes on a smooth path (the tilt that
// follows from its acceleration stays that of gentle flight), the climb spans 3 m of
// height, the hover turns about the vertical once in 18 s.
TEST(Flight, PatternsFlyTheirPaths) {
  FlightSettings settings;
  settings.pattern = FlightPattern::lawnmower;
  std::set<long> lanes;
  double steepest = 0;
  for (double t = 0; t < 180; t += 0.05) {
    const BodyState state = scenario_state(settings, t);
    lanes.insert(std::lround((state.position.y() + 2.25) / 1.5 * 100));  // hundredths of a lane
    const Eigen::Vector3d up = state.orientation * Eigen::Vector3d::UnitZ();
    steepest = std::max(steepest, std::acos(up.z()) * 180 / M_PI);
  }
  for (long lane : {0L, 100L, 200L, 300L}) EXPECT_TRUE(lanes.count(lane)) << "lane " << lane / 100;
  EXPECT_LT(steepest, 15.0);
  settings.pattern = FlightPattern::climb;
  double low = INFINITY, high = -INFINITY;
  for (double t = 0; t < 180; t += 0.5) {
    low = std::min(low, scenario_state(settings, t).position.z());
    high = std::max(high, scenario_state(settings, t).position.z());
  }
  EXPECT_NEAR(high - low, 3.0, 0.05);
  settings.pattern = FlightPattern::hover_turn;
  const auto yaw = [&](double t) {
    const Eigen::Vector3d forward = scenario_state(settings, t).orientation * Eigen::Vector3d::UnitX();
    return std::atan2(forward.y(), forward.x());
  };
  EXPECT_NEAR(std::remainder(yaw(4.5) - yaw(0), 2 * M_PI), M_PI / 2, 0.05);
  EXPECT_NO_THROW(simulate_flight([&] {
    FlightSettings short_flight = settings;
    short_flight.duration = 2;
    return short_flight;
  }()));
}
