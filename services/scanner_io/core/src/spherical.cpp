#include "scanbus/scanner_io/spherical.hpp"

#include <cmath>

namespace scanbus::scanner_io {

Eigen::Vector3f to_cartesian(double range, double yaw, double pitch) {
  return Eigen::Vector3d(range * std::cos(yaw) * std::sin(pitch), range * std::sin(yaw) * std::sin(pitch),
                         range * std::cos(pitch))
      .cast<float>();
}

bool in_gate(const SphericalMeasurement& measurement, const RangeGate& gate) {
  return std::isfinite(measurement.range) && measurement.range >= gate.min && measurement.range <= gate.max;
}

}  // namespace scanbus::scanner_io
