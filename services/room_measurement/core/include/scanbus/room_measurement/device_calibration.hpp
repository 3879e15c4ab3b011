// A scanning unit's own range bias, lever arm and servo offset, calibrated from several of its
// scans: one scan pins them only as far as its walls are seen from many angles
// (docs/room_evaluation.md), so every scan's information about them is summed (a joint fit of
// the unit's terms, each scan's walls and yaw error its own) and the result goes into the
// adjustment's calibrated values, its uncertainty into their priors.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "scanbus/room_measurement/room_measurement.hpp"

namespace scanbus::room_measurement {

struct UnitCalibration {
  size_t scans = 0;                      // scans pooled
  size_t rejected = 0;                   // scans with the terms estimated left out: far from the others
  double range_bias = 0, lever_arm = 0;  // m: corrections, as DeviceEstimate's
  double pitch_offset = 0;               // rad
  // One sigma each: the pooled information's (scaled by `scatter`) and the servo's own error at
  // each commanded pitch, which is the same in every scan and so is not averaged out by pooling
  // (carried through with the steps' prior: AdjustmentSettings::step_error_prior_deg).
  double range_bias_sigma = 0, lever_arm_sigma = 0, pitch_offset_sigma = 0;
  Eigen::Vector3d servo_sigmas = Eigen::Vector3d::Zero();  // that servo part alone, the terms in this order
  double scatter = 1;  // the scans' disagreement over what their information predicts (the sigmas
                       // are scaled up by its root: a scan's neighbouring points are not independent)
};

// Pools the scans whose device terms were estimated, applied or held (a unit far off is held by
// every scan's uncalibrated priors), leaving out those far from the others' agreement. Throws
// std::invalid_argument with fewer than two agreeing scans, or when together they do not pin
// the three terms.
UnitCalibration calibrate_unit(const std::vector<DeviceEstimate>& scans);

// The least prior apply_calibration sets (why: device_calibration.cpp).
struct CalibratedPriors {
  double range_bias, lever_arm, pitch_offset_deg;
};
constexpr CalibratedPriors kMinimumPriors{0.001, 0.001, 0.1};

// The calibration as the adjustment's calibrated values and priors.
void apply_calibration(const UnitCalibration& calibration, AdjustmentSettings& settings);

}  // namespace scanbus::room_measurement
