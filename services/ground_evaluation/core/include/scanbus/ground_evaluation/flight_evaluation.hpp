// A MAV log through the whole pipeline in one process, scored against its ground truth:
// the scan matcher, the pose estimator, the cloud built from the poses, and the boxes in
// it. Three heights side by side, as the MAV paper compares them: the barometer alone
// (the paper's "without laser scan matcher"), the barometer's first sample plus the
// integrated scan-matcher changes (its "with laser scan matcher", section 3.6), and the
// fusion. The DDS pipeline must reach the same figures (tests/integration).
#pragma once

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "scanbus/cloud_assembly/cloud_builder.hpp"
#include "scanbus/ground_evaluation/box_evaluation.hpp"
#include "scanbus/pose_estimation/height_fusion.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"
#include "scanbus/sensor_replay/mav_log.hpp"

namespace scanbus::ground_evaluation {

struct FlightEvaluationSettings {
  scan_matcher::MatcherSettings matcher;
  pose_estimation::FusionSettings fusion;
  cloud_assembly::ScanGating gating{30.0, M_PI / 2};  // the paper: 30 m, 90 degrees
  BoxSearchSettings boxes;
};

enum class HeightSource { Barometer = 0, ScanMatcher = 1, Fused = 2 };
constexpr const char* kHeightSourceNames[] = {"barometer", "scan_matcher", "fused"};

struct FlightEvaluation {
  size_t scans = 0, poses = 0, matches_failed = 0, changes_rejected = 0;
  double height_rmse[3] = {0, 0, 0};  // m against the truth, by HeightSource
  double fusion_ms_per_update = 0;    // wall time of the pose estimator per scan
  bool has_boxes = false;             // the log names its boxes (scenario IV)
  BoxEvaluation boxes[3];             // the cloud built with each height
  std::vector<Eigen::Vector3f> cloud[3];  // every return in the map frame, by HeightSource
};

// `progress(done, total)` is called now and then. Throws sensor_replay::MavLogError when
// the log lacks what the evaluation needs (laser_mount, origin, truth).
FlightEvaluation evaluate_flight(const sensor_replay::MavLog& log, const FlightEvaluationSettings& settings,
                                 const std::function<void(size_t, size_t)>& progress = {});

}  // namespace scanbus::ground_evaluation
