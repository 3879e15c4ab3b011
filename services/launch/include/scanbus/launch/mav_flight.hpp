// A simulated MAV flight through the real path for the main job: the flight written as a
// MAV log, then sensor_replay, scan_matcher, pose_estimation and cloud_assembly as separate
// processes on DDS; the poses and the assembled cloud come back over the bus and are
// scored against the flight's truth.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "scanbus/dds.hpp"
#include "scanbus/ground_evaluation/box_evaluation.hpp"
#include "scanbus/launch/system.hpp"

namespace scanbus::launch {

struct MavFlightOptions {
  int scenario = 4;
  double duration = 180;  // s of flight
  double rate = 8;        // replay, times real time
  bool progress = false;
  double timeout = 300;  // s
};

struct MavFlightResult {
  size_t scans = 0, poses = 0;
  double fused_rmse = 0, barometer_rmse = 0;  // m, height against the truth
  std::vector<Eigen::Vector3f> cloud;         // the flight's assembled cloud, map frame
  ground_evaluation::BoxEvaluation boxes;     // scenario IV
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();
};

// The services start in `system` (the log, the configs and the processes' logs in its work
// folder) and stay there, running, after the replay ends, until the caller stops it or lets
// it go. Throws std::runtime_error naming what failed (a process that died, with its log).
MavFlightResult run_mav_flight(System& system, const MavFlightOptions& options);

}  // namespace scanbus::launch
