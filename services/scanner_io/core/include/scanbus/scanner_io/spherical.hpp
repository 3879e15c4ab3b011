// Rotating-scanner measurements to Cartesian points (thesis eq. 3.10-3.12): yaw about z,
// pitch measured from the z axis, scanner at the origin, SI units.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace scanbus::scanner_io {

struct SphericalMeasurement {
  double stamp = 0;   // s
  uint32_t line = 0;  // device sequence number
  double yaw = 0;     // rad
  double pitch = 0;   // rad from the z axis
  double range = 0;   // m; 0 is the sensor's "no return"
  double signal = 0;
};

struct RangeGate {
  double min = 0.05;  // m: LIDAR-Lite v3 reports a few cm for no or bad returns
  double max = 40.0;  // m: its specified range
};

Eigen::Vector3f to_cartesian(double range, double yaw, double pitch);

bool in_gate(const SphericalMeasurement& measurement, const RangeGate& gate);

}  // namespace scanbus::scanner_io
