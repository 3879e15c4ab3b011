// The thesis scanner in a RoomModel: what the device would measure, revolution by
// revolution, with the LIDAR-Lite v3's range noise. Yaw carries over across revolutions.
#pragma once

#include <random>
#include <vector>

#include "scanbus/sim/room_model.hpp"
#include "scanbus/sim/scan_pattern.hpp"

namespace scanbus::sim {

struct SimulatedSample {
  double time;    // s since the scan started
  double yaw;     // rad, continuous
  double pitch;   // rad from the pole's axis
  double range;   // m; 0 when nothing was hit (the sensor's no-return value)
  double signal;  // device units, weaker with distance
};

class SimulatedScanner {
 public:
  SimulatedScanner(RoomModel room, ScanPattern pattern, double range_noise, unsigned seed);

  // The next revolution of scan `cycle` (revolution counts within that scan).
  std::vector<SimulatedSample> revolution(int revolution, int cycle);
  const ScanPattern& pattern() const { return pattern_; }

 private:
  RoomModel room_;
  ScanPattern pattern_;
  std::normal_distribution<double> noise_;
  std::mt19937 random_;
  double yaw_ = 0;
  double time_ = 0;
};

}  // namespace scanbus::sim
