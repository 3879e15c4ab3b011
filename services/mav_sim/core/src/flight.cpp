#include "scanbus/mav_sim/flight.hpp"

#include <GeographicLib/LocalCartesian.hpp>

#include "scanbus/atmosphere.hpp"
#include "scanbus/transforms/transform_buffer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>

#include "scanbus/units.hpp"

namespace scanbus::mav_sim {

namespace {

using transforms::from_rpy;

constexpr double kGravity = 9.81;

double wave(double amplitude, double period, double t, double phase = 0) {
  return amplitude * std::sin(2 * M_PI * t / period + phase);
}

// The lane of a lawnmower pattern after `passes` passes: 0, 1, 2, 3, 3, 2, 1, 0, 0, 1 ...
// The MAV moves to the next lane in the second around the end of a pass, where it nearly
// stands still along x (a smooth path: the attitude follows from its acceleration).
double lane(double passes) {
  constexpr long kLanes = 4;
  constexpr double kTurn = 0.05;  // of a pass, each side of its end
  const auto lane_of = [](long pass) {
    const long k = std::max(pass, 0L) % (2 * kLanes);
    return static_cast<double>(k < kLanes ? k : 2 * kLanes - 1 - k);
  };
  const long end = std::lround(passes);
  const double from_end = passes - static_cast<double>(end);
  if (std::abs(from_end) >= kTurn) return lane_of(static_cast<long>(std::floor(passes)));
  const double eased = (1 - std::cos(M_PI * (from_end + kTurn) / (2 * kTurn))) / 2;
  return lane_of(end - 1) + (lane_of(end) - lane_of(end - 1)) * eased;
}

Eigen::Vector3d pattern_position(const FlightSettings& s, double t) {
  const double h = s.height;
  switch (s.pattern) {
    case FlightPattern::lawnmower:
      return {5 - 5 * std::cos(M_PI * t / 20), 1.5 * lane(t / 20) - 2.25, h + wave(0.1, 23, t)};
    case FlightPattern::climb:
      return {5 - 5 * std::cos(2 * M_PI * t / 20), wave(0.3, 37, t), h + wave(1.5, 90, t)};
    case FlightPattern::hover_turn:
      return {4 + wave(0.1, 17, t), wave(0.1, 13, t, 1), h + wave(0.1, 11, t)};
    case FlightPattern::paper:
      break;
  }
  return Eigen::Vector3d::Zero();
}

Eigen::Vector3d scenario_position(const FlightSettings& s, double t) {
  if (s.pattern != FlightPattern::paper) return pattern_position(s, t);
  const double h = s.height;
  switch (s.scenario) {
    case 1:  // 10 m forward and back, 20 s a round, gently changing height
      return {5 - 5 * std::cos(2 * M_PI * t / 20), wave(0.3, 37, t), h + wave(0.4, 23, t) + wave(0.15, 7.1, t)};
    case 2:  // hovering about one spot
      return {wave(0.3, 17, t), wave(0.3, 13, t, 1), h + wave(0.3, 11, t)};
    case 3:  // steered by hand around the corner at (6, 2)
      return {4.5 + wave(1.5, 31, t), 0.8 + wave(1.2, 23, t, 0.5), h + wave(0.3, 19, t)};
    default:  // 8 m forward and back over the boxes at x = 4
      return {4 - 4 * std::cos(2 * M_PI * t / 24), wave(0.1, 29, t), h + wave(0.25, 17, t)};
  }
}

// Roll, pitch and yaw added to what the acceleration needs: wind gusts (II), a hand's
// unsteadiness (III).
Eigen::Vector3d scenario_disturbance(const FlightSettings& s, double t) {
  if (s.pattern == FlightPattern::hover_turn) return {0, 0, std::remainder(2 * M_PI * t / 18, 2 * M_PI)};
  if (s.pattern != FlightPattern::paper) return {0, 0, wave(0.05, 50, t)};
  switch (s.scenario) {
    case 1:
      return {0, 0, wave(0.05, 50, t)};
    case 2:
      return {(wave(12, 2.0, t) + wave(5, 0.77, t, 0.7)) * kDegree, wave(3, 2.5, t) * kDegree, wave(0.3, 40, t)};
    case 3:
      return {wave(3, 3.3, t) * kDegree, wave(3, 4.1, t, 1) * kDegree, wave(0.4, 45, t)};
    default:
      return {0, 0, wave(0.03, 50, t)};
  }
}

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

// Each side above 0 and under 5 m (NaN fails: minCoeff and maxCoeff may skip it).
bool box_size_ok(const Eigen::Vector3d& size) { return ((size.array() > 0) && (size.array() < 5)).all(); }

void validate(const FlightSettings& s) {
  check(s.scenario >= 1 && s.scenario <= 4, "scenario must be 1 to 4 (I to IV)");
  check(s.duration > 0 && s.duration <= 3600, "duration must be in (0, 3600] s");
  check(s.height >= 0.5 && s.height <= 25, "height must be 0.5 to 25 m");
  check(box_size_ok(s.box_size), "box size must be positive and under 5 m");
  check(s.laser.rate > 0 && s.noise.imu_rate > 0 && s.noise.gps_rate > 0 && s.noise.baro_rate > 0,
        "sensor rates must be positive");
  check(s.noise.gps_velocity_time > 0 && s.noise.gps_wander_time > 0, "GPS correlation times must be positive");
  check(s.noise.baro_wash_time > 0 && s.noise.baro_warmup_time > 0, "barometer correlation times must be positive");
  check(s.noise_scale >= 0 && s.noise_scale <= 10, "noise scale must be 0 to 10");
  check(s.laser.field_of_view > 0 && s.laser.field_of_view <= 2 * M_PI,
        "laser field of view must be in (0, 360] degrees");
  check(s.laser.step > 1e-4 && s.laser.field_of_view / s.laser.step < 20000, "laser step too small");
  if (const auto problem = terrain_problem(s.terrain)) throw std::invalid_argument("terrain: " + problem->message());
}

}  // namespace

SensorNoise with_gps(SensorNoise noise, GpsMode mode) {
  switch (mode) {
    case GpsMode::rtk_fixed:  // 1 cm jitter, about 1.5 cm (horizontal) and 3 cm (vertical) of wander
      noise.gps_horizontal = 0.01, noise.gps_vertical = 0.02;
      noise.gps_velocity_horizontal = 0.0005, noise.gps_velocity_vertical = 0.001;
      noise.gps_wander_time = 60;
      break;
    case GpsMode::rtk_float:  // about 0.23 m (horizontal) and 0.45 m (vertical) of wander
      noise.gps_horizontal = 0.05, noise.gps_vertical = 0.1;
      noise.gps_velocity_horizontal = 0.005, noise.gps_velocity_vertical = 0.01;
      noise.gps_wander_time = 120;
      break;
    case GpsMode::standalone:  // about 1.5 m (horizontal) and 3.8 m (vertical) of wander
      noise.gps_horizontal = 0.02, noise.gps_vertical = 0.05;
      noise.gps_velocity_horizontal = 0.02, noise.gps_velocity_vertical = 0.05;
      noise.gps_wander_time = 300;
      break;
  }
  noise.gps_velocity_time = 20;
  return noise;
}

BodyState scenario_state(const FlightSettings& s, double t) {
  BodyState state;
  state.position = scenario_position(s, t);
  // A multirotor tilts its thrust to accelerate: pitch forward, roll sideways.
  constexpr double dt = 0.01;
  const Eigen::Vector3d acceleration =
      (scenario_position(s, t + dt) - 2 * state.position + scenario_position(s, t - dt)) / (dt * dt);
  const Eigen::Vector3d extra = scenario_disturbance(s, t);
  const Eigen::Vector2d heading_frame = Eigen::Rotation2Dd(-extra.z()) * acceleration.head<2>();
  const double pitch = std::atan2(heading_frame.x(), kGravity + acceleration.z());
  const double roll = -std::atan2(heading_frame.y(), kGravity + acceleration.z());
  state.orientation = from_rpy(roll + extra.x(), pitch + extra.y(), extra.z());
  return state;
}

GroundWorld scenario_world(const FlightSettings& s) {
  if (s.scenario == 3)  // two 1 m blocks meeting in a concave corner at (6, 2)
    return GroundWorld({{{4, 3}, 0, {8, 2, 1.0}}, {{7, -1}, 0, {2, 6, 1.0}}}, s.terrain);
  if (s.scenario == 4) {  // two identical boxes side by side across the flight path
    const double gap = 0.5;
    const double offset = (s.box_size.y() + gap) / 2;
    return GroundWorld({{{4, -offset}, 0, s.box_size}, {{4, offset}, 0, s.box_size}}, s.terrain);
  }
  return GroundWorld({}, s.terrain);
}

namespace {

// META terrain_slope sx sy; terrain_mounds cx cy radius height ...; terrain_steps ax ay
// direction height width ...; terrain_roughness rms wavelength seed (docs/mav_log.md).
void write_terrain(const Terrain& terrain, std::map<std::string, std::vector<double>>& meta) {
  if (!terrain.slope.isZero()) meta["terrain_slope"] = {terrain.slope.x(), terrain.slope.y()};
  for (const Mound& m : terrain.mounds)
    meta["terrain_mounds"].insert(meta["terrain_mounds"].end(), {m.centre.x(), m.centre.y(), m.radius, m.height});
  for (const Step& st : terrain.steps)
    meta["terrain_steps"].insert(meta["terrain_steps"].end(),
                                 {st.at.x(), st.at.y(), st.direction, st.height, st.width});
  if (terrain.roughness > 0)
    meta["terrain_roughness"] = {terrain.roughness, terrain.roughness_wavelength,
                                 static_cast<double>(terrain.roughness_seed)};
}

Terrain read_terrain(const sensor_replay::MavLog& log) {
  Terrain terrain;
  auto values = [&](const char* name, size_t group) -> std::vector<double> {
    const auto found = log.meta.find(name);
    if (found == log.meta.end()) return {};
    if (found->second.size() % group != 0 || found->second.empty())
      throw sensor_replay::MavLogError(std::string("META ") + name + " needs groups of " + std::to_string(group) +
                                       " values");
    return found->second;
  };
  if (const auto v = values("terrain_slope", 2); !v.empty()) terrain.slope = {v[0], v[1]};
  const auto mounds = values("terrain_mounds", 4);
  for (size_t i = 0; i < mounds.size(); i += 4) {
    terrain.mounds.push_back({{mounds[i], mounds[i + 1]}, mounds[i + 2], mounds[i + 3]});
  }
  const auto steps = values("terrain_steps", 5);
  for (size_t i = 0; i < steps.size(); i += 5) {
    terrain.steps.push_back({{steps[i], steps[i + 1]}, steps[i + 2], steps[i + 3], steps[i + 4]});
  }
  if (const auto v = values("terrain_roughness", 3); !v.empty()) {
    if (!(v[2] >= 0 && v[2] <= 4294967295.0))
      throw sensor_replay::MavLogError("META terrain_roughness: the seed is out of range");
    terrain.roughness = v[0], terrain.roughness_wavelength = v[1], terrain.roughness_seed = static_cast<unsigned>(v[2]);
  }
  if (const auto problem = terrain_problem(terrain))
    throw sensor_replay::MavLogError("META terrain: " + problem->message());
  return terrain;
}

// The MAV holds its altitude: the ground under it must stay clear of it.
void check_clearance(const FlightSettings& s, const GroundWorld& world) {
  constexpr double kClearance = 0.5, kEvery = 0.1;  // m, s
  for (double t = 0; t < s.duration; t += kEvery) {
    const Eigen::Vector3d at = scenario_position(s, t);
    const double ground = world.height_at(at.head<2>());
    if (ground > at.z() - kClearance) {
      char what[160];
      std::snprintf(what, sizeof what,
                    "the terrain rises to %.2f m under the MAV at (%.2f, %.2f) at t = %.1f s, "
                    "within %.1f m of its altitude %.2f m",
                    ground, at.x(), at.y(), t, kClearance, at.z());
      throw std::invalid_argument(what);
    }
  }
}

}  // namespace

Eigen::Isometry3d laser_in_body(const LaserSettings& laser) {
  return transforms::from_xyz_rpy(laser.position, laser.rpy);
}

std::optional<GroundWorld> world_of_log(const sensor_replay::MavLog& log) {
  const auto scenario = log.meta.find("scenario");
  if (scenario == log.meta.end() || scenario->second.size() != 1) return std::nullopt;
  if (!(scenario->second[0] >= 1 && scenario->second[0] <= 4))
    throw sensor_replay::MavLogError("META scenario is not 1 to 4");
  FlightSettings settings;
  settings.scenario = static_cast<int>(scenario->second[0]);
  if (settings.scenario == 4) {
    const auto& box = log.meta_of("boxes", 3);
    settings.box_size = {box[0], box[1], box[2]};
    if (!box_size_ok(settings.box_size))
      throw sensor_replay::MavLogError("META boxes must be three sizes above 0 and under 5 m");
  }
  settings.terrain = read_terrain(log);
  return scenario_world(settings);
}

std::function<std::optional<double>(const Eigen::Vector2d&)> scored_ground_of_log(const sensor_replay::MavLog& log) {
  auto world = world_of_log(log);
  if (!world) return {};
  return [world = std::move(*world)](const Eigen::Vector2d& xy) { return world.scored_height(xy, kScoredEdgeMargin); };
}

namespace {

// Every error and sigma of the sensors times noise_scale (rates and correlation times stay).
FlightSettings with_errors_scaled(FlightSettings s) {
  SensorNoise& n = s.noise;
  for (double* sigma : {&s.laser.noise, &s.laser.range_bias, &s.laser.misalignment, &n.imu_roll_pitch, &n.imu_yaw,
                        &n.gps_horizontal, &n.gps_vertical, &n.gps_velocity_horizontal, &n.gps_velocity_vertical,
                        &n.baro_noise, &n.baro_wash, &n.baro_takeoff, &n.baro_warmup, &n.baro_weather})
    *sigma *= s.noise_scale;
  return s;
}

}  // namespace

sensor_replay::MavLog simulate_flight(const FlightSettings& settings) {
  validate(settings);
  const FlightSettings s = with_errors_scaled(settings);
  std::mt19937 random(s.seed);
  std::normal_distribution<double> gauss(0, 1);
  const GroundWorld world = scenario_world(s);
  check_clearance(s, world);
  // The flight's own errors, drawn once: the laser as mounted and its range offset, the
  // barometer's offset at take-off, its warm-up drift and the weather's trend.
  const double range_bias = s.laser.range_bias * gauss(random);
  const double misaligned_roll = s.laser.misalignment * gauss(random),
               misaligned_pitch = s.laser.misalignment * gauss(random);
  const double misaligned_yaw = s.laser.misalignment * gauss(random);  // within the scan plane
  const Eigen::Isometry3d mount = laser_in_body(s.laser) * from_rpy(misaligned_roll, misaligned_pitch, misaligned_yaw);
  const double baro_takeoff = s.noise.baro_takeoff * gauss(random), baro_warmup = s.noise.baro_warmup * gauss(random),
               baro_weather = s.noise.baro_weather * gauss(random);
  const GeographicLib::LocalCartesian local(s.origin.x(), s.origin.y(), s.origin.z());
  sensor_replay::MavLog log;
  log.meta["scenario"] = {static_cast<double>(s.scenario)};
  log.meta["origin"] = {s.origin.x(), s.origin.y(), s.origin.z()};
  log.meta["laser_mount"] = {s.laser.position.x(), s.laser.position.y(), s.laser.position.z(),
                             s.laser.rpy.x(),      s.laser.rpy.y(),      s.laser.rpy.z()};
  log.meta["true_laser_misalignment"] = {misaligned_roll, misaligned_pitch, misaligned_yaw};
  if (s.scenario == 4) log.meta["boxes"] = {s.box_size.x(), s.box_size.y(), s.box_size.z()};
  write_terrain(s.terrain, log.meta);

  const int rays = static_cast<int>(std::floor(s.laser.field_of_view / s.laser.step + 1e-9)) + 1;
  for (double t = 0; t < s.duration; t += 1 / s.laser.rate) {
    const BodyState body = scenario_state(s, t);
    const Eigen::Isometry3d laser = Eigen::Translation3d(body.position) * body.orientation * mount;
    sensor::LaserScan scan;
    scan.stamp = s.start_stamp + t;
    scan.angle_min = -(rays - 1) * s.laser.step / 2;
    scan.angle_increment = s.laser.step;
    scan.range_min = 0.05;
    scan.range_max = s.laser.range_max;
    for (int i = 0; i < rays; ++i) {
      const double angle = scan.angle_min + i * s.laser.step;
      const Eigen::Vector3d direction = laser.linear() * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0);
      const double range = world.cast(laser.translation(), direction) + range_bias + s.laser.noise * gauss(random);
      scan.ranges.push_back(range <= s.laser.range_max ? static_cast<float>(range) : INFINITY);
    }
    log.lasers.push_back(std::move(scan));
  }
  for (double t = 0; t < s.duration; t += 1 / s.noise.imu_rate) {
    const Eigen::Quaterniond error = from_rpy(s.noise.imu_roll_pitch * gauss(random),
                                              s.noise.imu_roll_pitch * gauss(random), s.noise.imu_yaw * gauss(random));
    log.imus.push_back({s.start_stamp + t, (scenario_state(s, t).orientation * error).normalized()});
  }
  Eigen::Vector3d wander = Eigen::Vector3d::Zero(), velocity_error = Eigen::Vector3d::Zero();
  const Eigen::Vector3d velocity_sigma(s.noise.gps_velocity_horizontal, s.noise.gps_velocity_horizontal,
                                       s.noise.gps_velocity_vertical);
  const double dt = 1 / s.noise.gps_rate, decay = std::exp(-dt / s.noise.gps_velocity_time);
  const auto wander_step = [&] {
    for (int axis = 0; axis < 3; ++axis) {
      velocity_error[axis] =
          decay * velocity_error[axis] + velocity_sigma[axis] * std::sqrt(1 - decay * decay) * gauss(random);
      wander[axis] += (velocity_error[axis] - wander[axis] / s.noise.gps_wander_time) * dt;
    }
  };
  // The receiver has been running before the flight: its wander starts as it is at any time.
  const double settled = 5 * std::max(s.noise.gps_velocity_time, s.noise.gps_wander_time);
  for (double t = 0; t < settled; t += dt) wander_step();
  // The stationary standard deviation of the leaky integral x' = v - x / T of a velocity
  // error v of correlation time tau: sigma_v T sqrt(tau / (tau + T)). The fix reports it.
  const double tau = s.noise.gps_velocity_time, leak = s.noise.gps_wander_time;
  const double wander_scale = leak * std::sqrt(tau / (tau + leak));
  for (double t = 0; t < s.duration; t += dt) {
    wander_step();
    const Eigen::Vector3d white(s.noise.gps_horizontal * gauss(random), s.noise.gps_horizontal * gauss(random),
                                s.noise.gps_vertical * gauss(random));
    const Eigen::Vector3d measured = scenario_state(s, t).position + wander + white;
    sensor_replay::GpsRecord fix;
    fix.stamp = s.start_stamp + t;
    local.Reverse(measured.x(), measured.y(), measured.z(), fix.latitude, fix.longitude, fix.altitude);
    fix.horizontal_sigma = std::hypot(s.noise.gps_horizontal, s.noise.gps_velocity_horizontal * wander_scale);
    fix.vertical_sigma = std::hypot(s.noise.gps_vertical, s.noise.gps_velocity_vertical * wander_scale);
    log.fixes.push_back(fix);
  }
  const double baro_step = 1 / s.noise.baro_rate, wash_decay = std::exp(-baro_step / s.noise.baro_wash_time);
  double wash = s.noise.baro_wash * gauss(random);
  for (double t = 0; t < s.duration; t += baro_step) {
    wash = wash_decay * wash + s.noise.baro_wash * std::sqrt(1 - wash_decay * wash_decay) * gauss(random);
    const double drift = baro_takeoff + baro_warmup * (1 - std::exp(-t / s.noise.baro_warmup_time)) + baro_weather * t;
    const double altitude =
        s.origin.z() + scenario_state(s, t).position.z() + drift + wash + s.noise.baro_noise * gauss(random);
    log.baros.push_back({s.start_stamp + t, pressure_at_altitude(altitude)});
  }
  for (double t = 0; t < s.duration; t += 0.01) {
    const BodyState body = scenario_state(s, t);
    log.truths.push_back({s.start_stamp + t, body.position, body.orientation});
  }
  return log;
}

}  // namespace scanbus::mav_sim
