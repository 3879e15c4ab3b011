// The room's walls fitted together with the scanner's own errors, and their uncertainty.
//
// Walls are planes, so errors of the device bend every wall the same way: a range bias moves
// each point along its ray, a lever arm (the LiDAR's optical centre off the pitch axis) and a
// pitch error move it across, and a once-per-turn yaw error of the pole (a gear's runout)
// turns it about the pole by an angle that varies with yaw. All are linear in small
// corrections, so one least-squares adjustment (each point weighted by its range noise)
// estimates each wall's line (offset and a small turn) and the device terms from the walls'
// points, and each servo step's own pitch error (shared by the step's rays) with a prior,
// eliminated step by step. A point's ray follows from its position: the scanner is at the
// origin and its pitch counts from the vertical (the thesis's eq. 3.10-3.12).
//
// Uncertainty: a bootstrap over pitch bins (whole revolutions, whose errors are shared) for
// noise, neighbouring points' correlation and the device terms' estimate (when estimated),
// widened by a calibrated factor; plus each term the data cannot pin down (an inferred wall's
// placement; the device terms when they are not estimated) moved by its sigma and propagated
// to the walls.
#pragma once

#include <Eigen/Core>

#include <vector>

#include "scanbus/room_measurement/walls.hpp"

namespace scanbus::room_measurement {

struct AdjustmentSettings {
  bool enabled = true;
  bool estimate_device = true;     // estimate the device terms (off: hold them at their calibrated values,
                                   // zero uncalibrated, their priors added to the sigmas;
                                   // docs/room_evaluation.md compares the two)
  double band = 0.05;              // m: a wall's points used, either side of its refined line; wider
                                   // takes in skirting, frames and furniture near the wall
  double band_noise_sigmas = 2.5;  // ...or this many sigmas of the range noise at a point's range, where
                                   // that is wider: a far wall's noise (5-7 cm at 5-7 m) cut at 5 cm
                                   // left its fit where it started (near-wall rooms' far walls 4 cm off)
  // The range noise, one sigma, at zero range and its growth per metre: LIDAR-Lite v3 as the
  // thesis quotes its reference [2] (2.12 cm at 1.5 m, 3.51 cm at 3 m). Also each point's
  // weight in the fit (only its shape counts: a unit noisier throughout weighs the same).
  double range_noise = 0.0073;            // m
  double range_noise_per_metre = 0.0093;  // m per m of range
  double pitch_bin_deg = 1.0;             // one servo step: its rays share the step's own pitch error (one
                                          // unknown per bin) and the bootstrap resamples whole bins
  // The device's errors, one sigma (priors when estimated; added to the sigmas when not):
  double range_bias_prior = 0.01;      // m: a LIDAR-Lite v3 offset-calibrated at one distance, to its 1 cm resolution
  double lever_arm_prior = 0.02;       // m: the optical centre's height over the pitch axis, uncalibrated
                                       // (the LiDAR's housing is 4 cm high)
  double pitch_error_prior_deg = 0.5;  // a standard servo's offset: half its 1-degree resolution
  double step_error_prior_deg = 0.5;   // each servo step's own pitch error (the same for every ray of the
                                       // step): half the servo's 1-degree resolution, as the offset's;
                                       // 0 leaves the steps' errors to the bootstrap alone; held at zero
                                       // with the device terms when they are not estimated
  double yaw_error_prior_deg = 0.3;    // the pole's once-per-turn yaw error, each of its sine and cosine
                                       // parts: a printed gear's runout (0.1 mm on a 20 mm pitch radius)
  // A unit's own terms as its calibration found them (the corrections `scanbus room measure`
  // prints, pooled over scans; the priors above then say how well it found them): estimated
  // about these, or held at them. Zero: an uncalibrated unit. The yaw error has none: its phase
  // follows where the pole stood at power-up.
  double calibrated_range_bias = 0;        // m, added to the range
  double calibrated_lever_arm = 0;         // m
  double calibrated_pitch_offset_deg = 0;  // added to the reported pitch
  int bootstrap = 100;                     // replicates; 0 skips the uncertainty
  double bootstrap_scale = 1.1;            // the bootstrap's sigmas widened by this: alone they held 67 % of walls
                                           // within 1 sigma and 92.6 % within 2 on the development sweep (the
                                           // errors' tails are heavier than a normal's); a calibrated factor, sized
                                           // there and checked on unseen sweeps (docs/room_evaluation.md, "The
                                           // sigmas' scale"); another scanner needs it measured again
};

// What one sigma of a servo step's own pitch error (the steps' prior) adds to a scan's
// AdjustedWalls::unit_rhs, its step named by the commanded pitch (in pitch bins, rounded): the
// same step errs the same way in every scan of a unit, so a calibration pooling the scans keeps
// this part whole instead of averaging it out (device_calibration.hpp).
struct StepLeak {
  long pitch_step = 0;
  Eigen::Vector3d unit_rhs = Eigen::Vector3d::Zero();
};

struct AdjustedWalls {
  std::vector<Eigen::Vector2d> normals;  // per wall, in room order
  std::vector<double> offsets;
  std::vector<Eigen::Vector2d> corners;  // corners[i] joins walls[i-1] and walls[i]
  std::vector<double> lengths, length_sigmas;
  std::vector<double> corner_sigmas;  // m: one sigma of each corner's distance from where it is
                                      // (the root of its covariance's trace)
  double area = 0, area_sigma = 0;
  // The device terms estimated; with device_held, what the fit wanted and was not applied.
  double range_bias = 0, lever_arm = 0;  // m: the corrections (added to the range; along "up")
  double pitch_offset = 0;               // rad, added to the reported pitch
  Eigen::Vector2d yaw_error{0, 0};       // rad: the yaw error's sine and cosine parts (of the reported yaw)
  bool device_held = false;              // estimated beyond 3 sigmas of their priors, the device terms were held at
                                         // their calibrated values (zero uncalibrated) and the walls fitted alone
                                         // (the priors in the sigmas)
  // What the points alone say about the unit's own terms (range bias, lever arm, pitch offset,
  // their priors taken out; the walls and the yaw error, whose phase is the scan's own,
  // eliminated with theirs): information (per m^2 and rad^2) and its right-hand side. A
  // calibration sums them over scans of one unit (device_calibration.hpp). Zero when the device
  // terms are not estimated.
  Eigen::Matrix3d unit_information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d unit_rhs = Eigen::Vector3d::Zero();
  std::vector<StepLeak> unit_step_leaks{};  // per servo step; empty without the steps' unknowns
};

// `walls` in room order with their inliers; an inferred wall (no inliers) is held where it was
// placed, its offset_sigma (its seen corner's uncertainty) added to the sigmas. Throws
// std::invalid_argument when fewer than 3.
AdjustedWalls adjust_walls(const std::vector<WallLine>& walls, const AdjustmentSettings& settings);

}  // namespace scanbus::room_measurement
