// The scanner's hardware on the host, for the firmware core: a DC motor with lag turning
// the pole, the encoder's counts and edge times, a servo with finite speed, and a
// LIDAR-Lite v3 whose 20 ms acquisitions ray-cast into a room. Simulated time advances
// only through advance() and the LiDAR's blocking acquisitions.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "hal.h"

namespace scanbus::sim {

// What makes a real device differ from the thesis's equations 3.10-3.12 (scanner_io's
// conversion): zero everywhere is the ideal device. These model the world, not the
// measurement: the room measurement never reads them (docs/room_simulation.md).
struct DeviceErrors {
  double lever_arm = 0;          // m: the LiDAR's optical centre sits this far off the pitch axis,
                                 // perpendicular to the beam (above it when the beam is level)
  double encoder_offset = 0;     // rad: the pole's true zero against the encoder's
  double yaw_eccentricity = 0;   // rad: amplitude of a once-a-turn yaw error (an eccentric gear)
  double yaw_phase = 0;          // rad: where around the turn that error peaks
  double servo_offset = 0;       // rad: every pitch off by this (the horn's spline)
  double servo_error = 0;        // rad, one sigma: each commanded angle's own repeatable error
  double range_bias = 0;         // m: added to every range (residual of the device's calibration)
  double range_noise_per_m = 0;  // m of noise sigma per metre of range, on top of range_noise
};

struct HardwareSettings {
  double range_noise = 0.02;          // m, one sigma at zero range (LIDAR-Lite v3: +-2.5 cm typical)
  double dropout = 0.002;             // probability an acquisition returns nothing
  double full_duty_rpm = 105;         // pole RPM at duty 255: 350 RPM gearbox output through 15/50
  double motor_time_constant = 0.15;  // s
  double servo_degrees_per_s = 300;   // standard servo: 0.2 s per 60 degrees
  double acquisition_time = 0.02;     // s: the LiDAR's 50 Hz
  double max_range = 40.0;            // m
  DeviceErrors errors;
  unsigned seed = 1;       // noise and dropouts (and the servo's errors when unit_seed is 0)
  unsigned unit_seed = 0;  // the servo's repeatable error at each commanded angle, the unit's own:
                           // the same in every scan of one unit; 0: drawn from `seed`
};

class SimulatedHardware : public scanner::Hal {
 public:
  // Range (m) from an origin along a unit direction, both in the scanner frame (the origin
  // is the LiDAR's optical centre), or nullopt when nothing is hit.
  using RangeFunction = std::function<std::optional<double>(const Eigen::Vector3d&, const Eigen::Vector3d&)>;

  SimulatedHardware(RangeFunction range, HardwareSettings settings);

  uint32_t millis() override;
  uint32_t micros() override;
  int32_t encoder_count() override;
  uint32_t encoder_edge_micros() override;
  void set_motor(uint8_t duty) override;
  void set_servo_degrees(uint8_t degrees) override;
  bool measure(uint16_t& range_cm, uint8_t& signal) override;
  void write(const char* text) override;
  int read() override;

  // Moves the simulation forward (motor, encoder, servo) in small steps.
  void advance(double seconds);
  double time() const { return time_; }
  double pole_angle() const { return pole_angle_; }  // rad since boot
  double pitch_degrees() const { return pitch_; }
  std::string take_output();
  void feed_input(const std::string& bytes);

 private:
  void step(double dt);

  RangeFunction range_;
  HardwareSettings settings_;
  std::mt19937 random_;
  std::normal_distribution<double> noise_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  std::vector<double> servo_errors_;  // rad, by commanded degree
  double time_ = 0;
  double pole_angle_ = 0;    // rad
  double pole_speed_ = 0;    // rad/s
  double target_speed_ = 0;  // rad/s from the duty
  double pitch_ = 90;        // degrees, actual servo position
  double pitch_target_ = 90;
  int32_t count_ = 0;
  double edge_time_ = 0;
  std::string output_, input_;
};

}  // namespace scanbus::sim
