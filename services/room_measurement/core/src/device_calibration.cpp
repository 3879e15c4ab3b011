#include "scanbus/room_measurement/device_calibration.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "scanbus/units.hpp"

namespace scanbus::room_measurement {

namespace {

constexpr double kChiSquareMedian = 2.366;   // of a chi-square with 3 degrees of freedom
constexpr double kChiSquareOutlier = 16.27;  // its 99.9 % point

struct Pooled {
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  Eigen::Vector3d terms = Eigen::Vector3d::Zero();
};

std::optional<Eigen::Vector3d> solve(const Eigen::Matrix3d& information, const Eigen::Vector3d& rhs) {
  const auto solver = information.ldlt();
  if (solver.info() != Eigen::Success || !solver.isPositive() || solver.vectorD().minCoeff() <= 0) return {};
  return solver.solve(rhs);
}

Pooled pool(const std::vector<const DeviceEstimate*>& scans) {
  Pooled p;
  for (const auto* scan : scans) p.information += scan->unit_information, p.rhs += scan->unit_rhs;
  const auto terms = solve(p.information, p.rhs);
  // The scans may see the terms from too few angles together: nothing to calibrate from.
  if (!terms) throw std::invalid_argument("the scans do not pin the unit's range bias, lever arm and servo offset");
  p.terms = *terms;
  return p;
}

// A scan's misfit to `terms` in its own information's units: chi-square with 3 degrees of
// freedom if that information were right.
double misfit(const DeviceEstimate& scan, const Eigen::Vector3d& terms) {
  const Eigen::Vector3d r = scan.unit_rhs - scan.unit_information * terms;
  return r.dot(scan.unit_information.ldlt().solve(r));
}

// ...to the others' terms: a pooled scan left out (it would pull the pool towards itself).
double misfit_to_others(const DeviceEstimate& scan, const Pooled& pooled, bool pooled_in) {
  if (!pooled_in) return misfit(scan, pooled.terms);
  const auto others = solve(pooled.information - scan.unit_information, pooled.rhs - scan.unit_rhs);
  return others ? misfit(scan, *others) : 0.0;  // the others alone pin nothing: no judging it
}

// A servo step's error e moves every kept scan's rhs by its leak times e (in prior sigmas): summed
// by commanded pitch, the pooled terms move by inverse * sum e, whatever the scans' number. Each
// scan's information already counts its own steps as independent (their prior, eliminated), so
// only what the scans share is added: the sums' outer products less each scan's own.
Eigen::Matrix3d servo_covariance(const std::vector<const DeviceEstimate*>& scans, const Eigen::Matrix3d& inverse) {
  std::map<long, Eigen::Vector3d> by_step;
  Eigen::Matrix3d leaked = Eigen::Matrix3d::Zero();
  for (const auto* scan : scans)
    for (const auto& leak : scan->unit_step_leaks) {
      by_step.try_emplace(leak.pitch_step, Eigen::Vector3d::Zero()).first->second += leak.unit_rhs;
      leaked -= leak.unit_rhs * leak.unit_rhs.transpose();
    }
  for (const auto& [step, sum] : by_step) leaked += sum * sum.transpose();
  return inverse * leaked * inverse;
}

}  // namespace

UnitCalibration calibrate_unit(const std::vector<DeviceEstimate>& scans) {
  std::vector<const DeviceEstimate*> candidates;
  for (const auto& scan : scans)
    if (scan.state != DeviceEstimate::State::NotEstimated) candidates.push_back(&scan);
  std::vector<const DeviceEstimate*> kept = candidates;
  auto too_few = [&] {
    if (kept.size() >= 2) return;
    throw std::invalid_argument(
        "a calibration needs at least two scans with the device terms estimated and agreeing (" +
        std::to_string(kept.size()) + " of " + std::to_string(scans.size()) + ")");
  };
  too_few();
  // A scan whose walls took up something the model lacks (clutter on a wall's line) disagrees
  // with the rest far beyond their usual spread: left out, and the rest pooled again.
  Pooled pooled = pool(kept);
  for (int round = 0; round < 5; ++round) {
    std::vector<double> misfits, spread;  // spread: the pooled scans' misfits
    for (const auto* scan : candidates) {
      const bool pooled_in = std::find(kept.begin(), kept.end(), scan) != kept.end();
      misfits.push_back(misfit_to_others(*scan, pooled, pooled_in));
      if (pooled_in) spread.push_back(misfits.back());
    }
    std::nth_element(spread.begin(), spread.begin() + static_cast<long>(spread.size() / 2), spread.end());
    const double usual = std::max(1.0, spread[spread.size() / 2] / kChiSquareMedian);
    std::vector<const DeviceEstimate*> agreeing;
    for (size_t i = 0; i < candidates.size(); ++i)
      if (misfits[i] <= kChiSquareOutlier * usual) agreeing.push_back(candidates[i]);
    if (agreeing == kept) break;
    kept = agreeing;
    too_few();
    pooled = pool(kept);
  }
  double chi_square = 0;
  for (const auto* scan : kept) chi_square += misfit(*scan, pooled.terms);
  UnitCalibration c;
  c.scans = kept.size();
  c.rejected = candidates.size() - kept.size();
  c.scatter = std::max(1.0, chi_square / (3.0 * static_cast<double>(kept.size() - 1)));
  const Eigen::Matrix3d inverse = pooled.information.ldlt().solve(Eigen::Matrix3d::Identity());
  // Under zero where the scans' steps leak in opposite ways: nothing shared to add.
  c.servo_sigmas = servo_covariance(kept, inverse).diagonal().cwiseMax(0.0).cwiseSqrt();
  const Eigen::Vector3d variances = inverse.diagonal() * c.scatter + c.servo_sigmas.cwiseAbs2();
  c.range_bias = pooled.terms[0], c.lever_arm = pooled.terms[1], c.pitch_offset = pooled.terms[2];
  c.range_bias_sigma = std::sqrt(variances[0]);
  c.lever_arm_sigma = std::sqrt(variances[1]);
  c.pitch_offset_sigma = std::sqrt(variances[2]);
  return c;
}

void apply_calibration(const UnitCalibration& calibration, AdjustmentSettings& settings) {
  settings.calibrated_range_bias = calibration.range_bias;
  settings.calibrated_lever_arm = calibration.lever_arm;
  settings.calibrated_pitch_offset_deg = calibration.pitch_offset / kDegree;
  // The sigmas carry the servo's own error at each commanded angle at the steps' prior; the
  // priors are still not let below kMinimumPriors, which were sized before that on the pooled
  // terms' errors over ten simulated units (up to 1.5 mm, 0.7 mm and 0.2 degree from the units'
  // own; docs/room_evaluation.md).
  settings.range_bias_prior = std::max(kMinimumPriors.range_bias, calibration.range_bias_sigma);
  settings.lever_arm_prior = std::max(kMinimumPriors.lever_arm, calibration.lever_arm_sigma);
  settings.pitch_error_prior_deg = std::max(kMinimumPriors.pitch_offset_deg, calibration.pitch_offset_sigma / kDegree);
}

}  // namespace scanbus::room_measurement
