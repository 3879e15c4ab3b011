#include "scanbus/room_measurement/device_calibration.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace scanbus::room_measurement {

UnitCalibration calibrate_unit(const std::vector<DeviceEstimate>& scans) {
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  std::vector<const DeviceEstimate*> used;
  for (const auto& scan : scans) {
    if (scan.state != DeviceEstimate::State::Applied) continue;
    information += scan.unit_information;
    rhs += scan.unit_rhs;
    used.push_back(&scan);
  }
  if (used.size() < 2)
    throw std::invalid_argument(
        "a calibration needs at least two scans whose device terms were estimated and applied (" +
        std::to_string(used.size()) + " of " + std::to_string(scans.size()) + ")");
  const auto pooled = information.ldlt();
  const Eigen::Vector3d terms = pooled.solve(rhs);
  // Each scan's misfit to the pooled terms, in its own information's units: chi-square with
  // 3 (n - 1) degrees of freedom if its information were right.
  double chi_square = 0;
  for (const auto* scan : used) {
    const Eigen::Vector3d misfit = scan->unit_rhs - scan->unit_information * terms;
    chi_square += misfit.dot(scan->unit_information.ldlt().solve(misfit));
  }
  UnitCalibration c;
  c.scans = used.size();
  c.scatter = std::max(1.0, chi_square / (3.0 * static_cast<double>(used.size() - 1)));
  const Eigen::Vector3d variances = pooled.solve(Eigen::Matrix3d::Identity()).diagonal() * c.scatter;
  c.range_bias = terms[0], c.lever_arm = terms[1], c.pitch_offset = terms[2];
  c.range_bias_sigma = std::sqrt(variances[0]);
  c.lever_arm_sigma = std::sqrt(variances[1]);
  c.pitch_offset_sigma = std::sqrt(variances[2]);
  return c;
}

void apply_calibration(const UnitCalibration& calibration, AdjustmentSettings& settings) {
  constexpr double kDegree = M_PI / 180;
  settings.calibrated_range_bias = calibration.range_bias;
  settings.calibrated_lever_arm = calibration.lever_arm;
  settings.calibrated_pitch_offset_deg = calibration.pitch_offset / kDegree;
  // Floors: the config's smallest priors (a prior of zero would hold a term without saying so).
  settings.range_bias_prior = std::max(1e-4, calibration.range_bias_sigma);
  settings.lever_arm_prior = std::max(1e-4, calibration.lever_arm_sigma);
  settings.pitch_error_prior_deg = std::max(1e-3, calibration.pitch_offset_sigma / kDegree);
}

}  // namespace scanbus::room_measurement
