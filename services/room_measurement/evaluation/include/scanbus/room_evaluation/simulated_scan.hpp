// A full scan of a simulated room without processes or DDS: the firmware core on the
// simulated hardware, its lines parsed by scanner_io's core. For the room evaluation, the
// accuracy tests and benchmarks that need realistic clouds fast.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "scanbus/sim/room_model.hpp"
#include "scanbus/sim/simulated_hardware.hpp"

namespace scanbus::room_evaluation {

struct SimulatedScanSettings {
  int resolution = 0;              // Table 4.2 setting
  int cycles = 3;                  // interleaved scans (eq. 4.9); the thesis's clouds have ~18,500 points
  sim::HardwareSettings hardware;  // the device: noise, dropouts, imperfections, seed
};

std::vector<Eigen::Vector3f> simulated_scan(const sim::RoomModel& room, const SimulatedScanSettings& settings);

}  // namespace scanbus::room_evaluation
