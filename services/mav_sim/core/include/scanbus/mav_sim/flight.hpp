// The MAV paper's four scenarios, flown in simulation with ground truth: I forward flight
// back and forth over flat ground, II rotational hover in wind (roll oscillation) over flat
// ground, III hand-steered motion over a corner-like ground (two raised blocks meeting in
// a corner), IV forward flight over two identical boxes. The sensors are sampled with the
// paper's rates and realistic noise, and written as a MAV log.
#pragma once

#include <Eigen/Geometry>

#include <functional>
#include <optional>
#include <string>

#include "scanbus/mav_sim/ground_world.hpp"
#include "scanbus/sensor_replay/mav_log.hpp"

namespace scanbus::mav_sim {

// What the simulated sensors get wrong is a model of the sensors and of flying them (data
// sheets and effects named beside each value, docs/mav_log.md), not of the pose estimation:
// several effects here are outside the fusion's model on purpose (a barometer offset at
// take-off, its warm-up drift and the weather's trend, the propellers' correlated wash, a
// laser mounted slightly off its drawing, a range bias). Errors "per flight" are drawn once
// from the seed. FlightSettings::noise_scale multiplies every error and sigma here.
struct LaserSettings {
  double rate = 30;                        // Hz (the paper's laser)
  double field_of_view = M_PI / 2;         // rad, centred on straight down (the paper keeps 90 degrees)
  double step = 0.25 * M_PI / 180;         // rad between rays
  double noise = 0.02;                     // m, Gaussian per range (a UTM-30LX class scanner: +-30 mm
                                           // to 10 m on its data sheet; grass and soil are worse than its target)
  double range_bias = 0.01;                // m, sigma of an offset of every range, per flight (within that +-30 mm)
  double misalignment = 0.3 * M_PI / 180;  // rad, sigma per axis of the mount's rotation away from its
                                           // drawing, per flight (a bracket, not calibrated); the log
                                           // carries the drawing
  double range_max = 30;                   // m
  // The laser in base_link as drawn: 10 cm below the centre, its x axis straight down and its z axis
  // forward, so its scan plane is the body's y-z plane (a push-broom across the flight) and
  // turns with the roll. As x y z roll pitch yaw: a pitch of +90 degrees.
  Eigen::Vector3d position{0, 0, -0.1};
  Eigen::Vector3d rpy{0, M_PI / 2, 0};
};

// A GPS receiver's modes (u-blox F9P class data sheet figures): RTK with the ambiguities fixed
// (1 cm + 1 ppm horizontal, about twice that vertical), RTK float (decimetres) and standalone,
// without corrections (metres of wander over minutes).
enum class GpsMode { rtk_fixed, rtk_float, standalone };

struct SensorNoise {
  double imu_rate = 10;                      // Hz (the paper's pose rate)
  double imu_roll_pitch = 0.3 * M_PI / 180;  // rad, white (an AHRS's attitude in flight)
  double imu_yaw = 1.0 * M_PI / 180;         // rad, white
  // GPS as the MAV's navigation solution delivers it: slow wander from a velocity error
  // (first-order Gauss-Markov, integrated with a leak that bounds it) and jitter from fix to
  // fix. The receiver reports the sigma its error really has (the stationary sigma of both).
  // Defaults: RTK fixed (with_gps()). A receiver that wanders by metres smears a cloud built
  // over several passes however good the height is.
  double gps_rate = 10;                                                    // Hz
  double gps_horizontal = 0.01, gps_vertical = 0.02;                       // m, white
  double gps_velocity_horizontal = 0.0005, gps_velocity_vertical = 0.001;  // m/s, the wander's velocity error
  double gps_velocity_time = 20;                                           // s, its correlation time
  double gps_wander_time = 60;                                             // s, the leak that bounds the wander
  // Barometer (an MS5611 class sensor).
  double baro_rate = 10;          // Hz
  double baro_noise = 0.1;        // m, white: the data sheet's 10 cm resolution
  double baro_wash = 0.2;         // m, the propellers' wash and gusts, correlated over baro_wash_time
  double baro_wash_time = 1.0;    // s
  double baro_takeoff = 0.15;     // m, sigma per flight: referenced on the ground, off once the
                                  // propellers spin up (ground effect, the wait before take-off)
  double baro_warmup = 0.3;       // m, sigma per flight: the sensor warming in flight, reached
                                  // over baro_warmup_time (exponentially)
  double baro_warmup_time = 100;  // s
  double baro_weather = 0.001;    // m/s, sigma per flight: the weather's pressure trend (about
                                  // 1 hPa in 2 hours)
};

// `noise` with the GPS part of a receiver in `mode`.
SensorNoise with_gps(SensorNoise noise, GpsMode mode);

// How the MAV moves over the scenario's ground: the paper's own motion for each scenario,
// or a survey pattern over the same ground.
enum class FlightPattern {
  paper,       // the scenario's motion (I forward and back, II hover in wind, III by hand, IV over the boxes)
  lawnmower,   // passes 10 m long along x, 20 s each, on four lanes 1.5 m apart (y -2.25 to 2.25 m), and back
  climb,       // scenario I's passes while climbing and descending 1.5 m over 90 s
  hover_turn,  // hovering over (4, 0) and turning about the vertical, a full turn in 18 s
};

struct FlightSettings {
  int scenario = 1;  // 1..4 as in the paper
  FlightPattern pattern = FlightPattern::paper;
  double duration = 180;                           // s (scenario I: about 3 minutes)
  double height = 3.0;                             // m above the ground at the map origin, on average (the MAV holds
                                                   // its altitude: over a terrain its clearance changes)
  Eigen::Vector3d box_size{0.6, 0.4, 0.3};         // scenario IV: length (along the flight), width, height
  Terrain terrain;                                 // the ground under every scenario (flat by default, as in the paper)
  double start_stamp = 1700000000.0;               // s, the first sample's stamp
  Eigen::Vector3d origin{52.5163, 13.3777, 34.0};  // lat, lon (deg), alt (m) of the map origin
  unsigned seed = 1;
  LaserSettings laser;
  SensorNoise noise;
  double noise_scale = 1;  // multiplies every sensor error and sigma (laser's and noise's)
};

struct BodyState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // base_link in the map frame
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// Ground truth of the scenario at time t (s since the start).
BodyState scenario_state(const FlightSettings& settings, double t);
GroundWorld scenario_world(const FlightSettings& settings);
// The laser's pose in base_link.
Eigen::Isometry3d laser_in_body(const LaserSettings& laser);

// The true ground of a simulated flight's log (its META scenario, boxes and terrain_*
// records), or none for a log that does not say (a real flight).
std::optional<GroundWorld> world_of_log(const sensor_replay::MavLog& log);

// Ground cloud points this near a box's edge or a step's ramp are not scored (m).
constexpr double kScoredEdgeMargin = 0.1;

// What a ground model of the log's flight is scored against: its world's scored_height with
// kScoredEdgeMargin, or an empty function for a log that does not carry its ground.
std::function<std::optional<double>(const Eigen::Vector2d&)> scored_ground_of_log(const sensor_replay::MavLog& log);

// Flies the scenario and returns every sensor sample and the truth (at 100 Hz). Throws
// std::invalid_argument naming a setting out of range (also a terrain that comes within
// 0.5 m of the MAV).
sensor_replay::MavLog simulate_flight(const FlightSettings& settings);

}  // namespace scanbus::mav_sim
