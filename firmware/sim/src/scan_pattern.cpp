#include "scanbus/sim/scan_pattern.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace scanbus::sim {

SpeedSetting speed_setting(int resolution) {
  switch (resolution) {
    case 0: return {12.0};
    case 1: return {20.0};
    case 2: return {28.0};
  }
  throw std::invalid_argument("resolution must be 0, 1 or 2, got " + std::to_string(resolution));
}

double ScanPattern::yaw_step() const { return 2 * M_PI * (rpm / 60.0) / sample_rate; }

double ScanPattern::revolution_period() const { return 60.0 / rpm; }

int ScanPattern::samples_per_revolution() const {
  return static_cast<int>(std::floor(revolution_period() * sample_rate));
}

double ScanPattern::pitch(int revolution, int cycle) const {
  // Eq. 4.9 shifts the start by one degree per cycle, modulo the pitch step, so that
  // successive scans interleave their pitch rings.
  const double degree = M_PI / 180.0;
  const int shifts = std::max(1, static_cast<int>(std::lround(pitch_step / degree)));
  return pitch_start + (cycle % shifts) * degree + revolution * pitch_step;
}

}  // namespace scanbus::sim
