// A full scan of a simulated room without processes or DDS: the firmware core on the
// simulated hardware, its lines parsed by scanner_io's core. For accuracy tests and
// benchmarks that need realistic clouds fast.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "scanbus/sim/room_model.hpp"

namespace scanbus::test_support {

struct SimulatedScanSettings {
  int resolution = 0;     // Table 4.2 setting
  int cycles = 3;         // interleaved scans (eq. 4.9); the thesis's clouds have ~18,500 points
  double noise = 0.02;    // m
  double dropout = 0.002;
  unsigned seed = 1;
};

std::vector<Eigen::Vector3f> simulated_scan(const sim::RoomModel& room, const SimulatedScanSettings& settings);

}  // namespace scanbus::test_support
