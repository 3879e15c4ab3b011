#include "scanbus/sim/simulated_hardware.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace scanbus::sim {

namespace {

// Encoder counts per pole revolution: 3 per motor turn, 42.875:1 gearbox, 50/15 gears.
constexpr double kCountsPerRevolution = 428.75;
constexpr double kStep = 0.0002;  // s: edges at 28 RPM are 5 ms apart

}  // namespace

SimulatedHardware::SimulatedHardware(RangeFunction range, HardwareSettings settings)
    : range_(std::move(range)), settings_(settings), random_(settings.seed), noise_(0.0, 1.0) {
  // Drawn only when asked for, so an ideal device's noise sequence stays what it was.
  servo_errors_.assign(181, settings.errors.servo_offset);
  if (settings.errors.servo_error > 0) {
    std::normal_distribution<double> servo(0.0, settings.errors.servo_error);
    std::seed_seq unit_stream{settings.unit_seed, 0x5e7u};  // not the stream the unit's other errors came from
    std::mt19937 unit(unit_stream);
    for (double& error : servo_errors_) error += servo(settings.unit_seed != 0 ? unit : random_);
  }
}

uint32_t SimulatedHardware::millis() { return static_cast<uint32_t>(time_ * 1e3); }
uint32_t SimulatedHardware::micros() { return static_cast<uint32_t>(time_ * 1e6); }
int32_t SimulatedHardware::encoder_count() { return count_; }
uint32_t SimulatedHardware::encoder_edge_micros() { return static_cast<uint32_t>(edge_time_ * 1e6); }

void SimulatedHardware::set_motor(uint8_t duty) {
  target_speed_ = settings_.full_duty_rpm * duty / 255.0 * 2 * M_PI / 60.0;
}

void SimulatedHardware::set_servo_degrees(uint8_t degrees) { pitch_target_ = std::min<double>(degrees, 180); }

bool SimulatedHardware::measure(uint16_t& range_cm, uint8_t& signal) {
  // The ray leaves at the start of the acquisition, along the true pole and servo angles,
  // from the LiDAR's optical centre.
  const DeviceErrors& e = settings_.errors;
  const double pitch = pitch_ * M_PI / 180.0 + servo_errors_[static_cast<size_t>(std::lround(pitch_target_))];
  const double yaw = pole_angle_ + e.encoder_offset + e.yaw_eccentricity * std::sin(pole_angle_ + e.yaw_phase);
  const Eigen::Vector3d direction(std::cos(yaw) * std::sin(pitch), std::sin(yaw) * std::sin(pitch), std::cos(pitch));
  const Eigen::Vector3d up(-std::cos(yaw) * std::cos(pitch), -std::sin(yaw) * std::cos(pitch), std::sin(pitch));
  const std::optional<double> hit = range_(e.lever_arm * up, direction);
  const bool dropout = uniform_(random_) < settings_.dropout;
  if (!hit || *hit > settings_.max_range || dropout) {
    range_cm = 1;  // what a LIDAR-Lite v3 reports without a return
    signal = 0;
  } else {
    const double sigma = settings_.range_noise + e.range_noise_per_m * *hit;
    const double measured = std::max(0.01, *hit + e.range_bias + sigma * noise_(random_));
    range_cm = static_cast<uint16_t>(std::lround(measured * 100.0));
    signal = static_cast<uint8_t>(std::clamp(255.0 / (1.0 + *hit * *hit / 25.0), 1.0, 255.0));
  }
  advance(settings_.acquisition_time);
  return true;
}

void SimulatedHardware::write(const char* text) { output_ += text; }

int SimulatedHardware::read() {
  if (input_.empty()) return -1;
  const int byte = static_cast<unsigned char>(input_.front());
  input_.erase(input_.begin());
  return byte;
}

std::string SimulatedHardware::take_output() {
  std::string out;
  out.swap(output_);
  return out;
}

void SimulatedHardware::feed_input(const std::string& bytes) { input_ += bytes; }

void SimulatedHardware::advance(double seconds) {
  while (seconds > 1e-12) {
    const double dt = std::min(seconds, kStep);
    step(dt);
    seconds -= dt;
  }
}

void SimulatedHardware::step(double dt) {
  pole_speed_ += (target_speed_ - pole_speed_) * (1.0 - std::exp(-dt / settings_.motor_time_constant));
  pole_angle_ += pole_speed_ * dt;
  const double max_move = settings_.servo_degrees_per_s * dt;
  pitch_ += std::clamp(pitch_target_ - pitch_, -max_move, max_move);
  time_ += dt;
  const auto count = static_cast<int32_t>(std::floor(pole_angle_ / (2 * M_PI) * kCountsPerRevolution));
  if (count != count_) {
    // Time of the edge within this step, so the firmware's interpolation sees true edges.
    const double edge_angle = count * 2 * M_PI / kCountsPerRevolution;
    edge_time_ = pole_speed_ > 0 ? time_ - (pole_angle_ - edge_angle) / pole_speed_ : time_;
    count_ = count;
  }
}

}  // namespace scanbus::sim
