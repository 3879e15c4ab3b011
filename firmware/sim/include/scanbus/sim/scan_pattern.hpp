// The thesis scanner's motion: the pole turns at constant speed while the LiDAR samples
// at 50 Hz; after each full yaw revolution the servo steps the pitch (section 4.1).
#pragma once

#include <cstdint>

namespace scanbus::sim {

struct SpeedSetting {
  double rpm;
};

// Table 4.2: res 0, 1, 2.
SpeedSetting speed_setting(int resolution);

struct ScanPattern {
  double pitch_start = 42.0 * 3.14159265358979323846 / 180.0;  // rad from the pole's axis
  double pitch_step = 3.0 * 3.14159265358979323846 / 180.0;    // rad per revolution
  int pitch_steps = 27;                                         // 81 degree field of view
  double sample_rate = 50.0;                                    // Hz, LIDAR-Lite v3 as used
  double rpm = 20.0;

  double yaw_step() const;             // rad between samples
  double revolution_period() const;    // s
  int samples_per_revolution() const;  // whole samples that fit in one turn
  // Pitch of a revolution in scan `cycle` (eq. 4.9: start shifted one degree per cycle).
  double pitch(int revolution, int cycle) const;
};

}  // namespace scanbus::sim
