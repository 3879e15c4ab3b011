// A MAV log through the whole pipeline in one process, scored against its ground truth:
// the scan matcher, the pose estimator, the cloud built from the poses, and the boxes in
// it. Four heights side by side: as the MAV paper compares them, the barometer alone
// (the paper's "without laser scan matcher") and the barometer's first sample plus the
// integrated scan-matcher changes (its "with laser scan matcher", section 3.6); the GPS
// altitude alone; and the fusion, as each pose left its window (settled, what the cloud is
// built from; the height as first solved is scored beside it). The DDS pipeline must reach the same figures
// (tests/integration).
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scanbus/cloud_assembly/cloud_builder.hpp"
#include "scanbus/cloud_assembly/elevation_grid.hpp"
#include "scanbus/ground_evaluation/box_evaluation.hpp"
#include "scanbus/pose_estimation/height_fusion.hpp"
#include "scanbus/pose_estimation/scan_plane_calibration.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"
#include "scanbus/sensor_replay/mav_log.hpp"

namespace scanbus::ground_evaluation {

// The scan matcher's configuration as the MAV flies it: config/mav/scan_matcher.yaml (the
// file the deployment reads, compiled in; it says why each setting differs from the default).
const char* mav_scan_matcher_config();
// Its `scan_matcher.matcher` section as settings.
scan_matcher::MatcherSettings mav_matcher_settings();

struct FlightEvaluationSettings {
  scan_matcher::MatcherSettings matcher = mav_matcher_settings();
  pose_estimation::FusionSettings fusion;
  bool ground_clearance = true;                 // false: the fusion of barometer and scan matcher alone
  bool settled_heights = true;                  // the fused height as it settled; false: as first solved
  sensor::RangeGate gating{0, 30.0, M_PI / 2};  // the paper: 30 m, 90 degrees
  BoxSearchSettings boxes;
  cloud_assembly::ElevationGridSettings elevation;  // the fused cloud's elevation grid
  double scan_plane_rotation = 0;                   // rad, the laser's calibrated turn in its scan plane
                                                    // after the log's laser_mount (calibrate_scan_plane)
  // The true ground's height at (x, y), none where a point is not scored (near an edge); empty
  // when the flight's ground is not known (a real flight): no ground-model error then.
  std::function<std::optional<double>(const Eigen::Vector2d&)> true_ground;
};

// A ground cloud's heights against the true ground, over the points where it is scored.
struct GroundModelError {
  size_t points = 0;                           // scored
  double rmse = NAN, median = NAN, p95 = NAN;  // m, of the height error (median and p95 of its size)
  double bias = NAN;                           // m, the mean signed error (+: the cloud lies high)
  // The plane through the cloud's scored points against the plane through the true ground at
  // the same places (least squares, dz/dx and dz/dy): does the cloud keep the terrain's tilt.
  Eigen::Vector2d slope{NAN, NAN}, true_slope{NAN, NAN};
  double slope_error = NAN;  // |slope - true_slope| / |true_slope|; NaN when the truth tilts under 1 %
};
GroundModelError ground_model_error(const std::vector<Eigen::Vector3f>& cloud,
                                    const std::function<std::optional<double>(const Eigen::Vector2d&)>& true_ground);

// The truth for an elevation grid's cells: the true ground averaged over the square cell
// centred at a point (what a cell's mean height estimates), none where any part of the cell
// is not scored: a cell an edge crosses mixes two levels and is no measure of the grid.
// Sampled every 0.1 m or closer: an edge crossing the cell passes within 0.071 m of a sample,
// so a truth that leaves out 0.1 m around its edges (scored_height) catches it.
std::function<std::optional<double>(const Eigen::Vector2d&)> cell_average_truth(
    std::function<std::optional<double>(const Eigen::Vector2d&)> true_ground, double cell_size);

// A height over time, interpolated linearly between samples (held beyond them); samples
// are added in time order.
class HeightSeries {
 public:
  static HeightSeries truth_of(const sensor_replay::MavLog& log);  // base_link's true height
  void add(double stamp, double value) { samples_.emplace_back(stamp, value); }
  double at(double stamp) const;  // the series must not be empty

 private:
  std::vector<std::pair<double, double>> samples_;  // by stamp
};

// Root mean square of each height's difference from the truth at its stamp (stamp, height
// pairs); NaN when there are none.
double height_rmse(const std::vector<std::pair<double, double>>& stamped_heights, const HeightSeries& truth);

enum class HeightSource { Barometer = 0, ScanMatcher = 1, Fused = 2, Gps = 3 };
constexpr int kHeightSources = 4;
constexpr const char* kHeightSourceNames[kHeightSources] = {"barometer", "scan_matcher", "fused", "gps"};

struct HeightSample {
  double stamp = 0, truth = 0;
  double height[kHeightSources] = {0, 0, 0, 0};  // by HeightSource (GPS: NaN in a log without fixes)
  double clearance = NAN;    // m above the ground under the pose's scan (its median return), NaN when none
  double fused_sigma = NAN;  // m, the standard deviation the pose carries for its fused height
  // The fused height and its sigma as first solved, on rt/pose (the fused height above is the
  // settled one, PoseEstimator::take_settled, which places the scans).
  double immediate = NAN, immediate_sigma = NAN;
};

struct FlightEvaluation {
  size_t scans = 0, poses = 0, matches_failed = 0, changes_rejected = 0;
  size_t clearances = 0;                              // poses whose scan showed the ground
  size_t ground_cells = 0;                            // corners of the fusion's elevation map at the end
  double height_rmse[kHeightSources] = {0, 0, 0, 0};  // m against the truth, by HeightSource (NaN: no such height)
  double fusion_ms_per_update = 0;                    // wall time of the pose estimator per scan
  double fused_within_sigma[2] = {NAN, NAN};      // share of poses whose fused height is within 1 and 2 of its sigmas
  double immediate_rmse = NAN;                    // m, of the fused heights as first solved
  double immediate_within_sigma[2] = {NAN, NAN};  // and their share within 1 and 2 sigmas
  bool has_boxes = false;                         // the log names its boxes (scenario IV)
  BoxEvaluation boxes[kHeightSources];            // the cloud built with each height
  bool has_ground = false;                        // the true ground is known (settings.true_ground)
  GroundModelError ground[kHeightSources];        // the cloud built with each height against it
  // The cloud built with the true height, every other sensor (position, attitude, laser) as
  // flown: the part of the ground's error that no height estimate can remove.
  GroundModelError ground_at_true_height;
  std::vector<Eigen::Vector3f> cloud[kHeightSources];  // every return in the map frame, by HeightSource
  cloud_assembly::ElevationGrid elevation;             // of the fused cloud (no cells when it is empty)
  GroundModelError elevation_error;   // its cells' heights against the true ground (cell_average_truth)
  std::vector<HeightSample> heights;  // one per pose
};

// `progress(done, total)` is called now and then. Throws sensor_replay::MavLogError when
// the log lacks what the evaluation needs (laser_mount, origin, truth).
FlightEvaluation evaluate_flight(const sensor_replay::MavLog& log, const FlightEvaluationSettings& settings,
                                 const std::function<void(size_t, size_t)>& progress = {});

// The laser's rotation in its scan plane from a log that turns on the spot (a hover-turn), with
// the log's IMU attitudes and its META laser_mount; throws MavLogError when the log has no
// laser_mount.
pose_estimation::ScanPlaneCalibration calibrate_scan_plane(const sensor_replay::MavLog& log);

}  // namespace scanbus::ground_evaluation
