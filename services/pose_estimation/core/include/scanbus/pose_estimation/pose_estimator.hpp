// The MAV's pose from its sources, one pose per scan-matcher result: height from the
// HeightFusion (barometer, GPS altitude, scan-matcher height changes, the ground the scans
// see), horizontal position
// from GPS in a local east-north-up frame, attitude from the IMU. A result waits until the
// IMU and GPS have samples on both sides of its stamp and the barometer and the scan theirs,
// or until `max_wait` of newer data shows they will not come.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "scanbus/config.hpp"
#include "scanbus/pose_estimation/height_fusion.hpp"
#include "scanbus/pose_estimation/laser_height.hpp"
#include "scanbus/sensor/laser_scan.hpp"
#include "scanbus/transforms/transform_buffer.hpp"

namespace scanbus::pose_estimation {

struct PoseEstimatorSettings {
  FusionSettings fusion;
  Eigen::Isometry3d laser_in_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d origin{0, 0, 0};  // latitude, longitude (deg), altitude (m) of the map origin
  double max_wait = 0.5;            // s of newer data after which a result goes ahead without IMU/GPS
  bool ground_clearance = true;     // the scans' ground returns enter the fusion
  bool gps_altitude = true;         // GPS altitudes enter the fusion, weighted by the fix's sigma
};

// Section `pose_estimation` of config/services/pose_estimation.yaml (angles in degrees
// there, radians here).
PoseEstimatorSettings pose_estimator_settings_from_config(const Config& section);

struct EstimatedPose {
  double stamp = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // base_link in the map frame (ENU, m)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d position_sigma = Eigen::Vector3d::Zero();  // m
  bool has_attitude = false, has_position = false;           // false: held from the nearest sample
  bool match_used = false;                                   // the scan matcher's height change entered
  std::optional<double> height_change;                       // m, from the match (before the fusion's gate)
  std::optional<double> clearance;                           // m above the ground its scan saw (the median return)
};

// A pose as it settled: `first_solved` with `settled`'s height and sigma, unless the window
// widened the sigma more than twice or it is unknown (then none: the first solve stands).
// Solving with more samples never widens a least-squares height's sigma; the robust losses
// do, when they came to discount the node's own cells (a step's edge), and its height then
// floats (0.29 m off, sigma 0.30 m, on the steps).
std::optional<EstimatedPose> settled_pose(const EstimatedPose& first_solved, const SettledHeight& settled);

class PoseEstimator {
 public:
  explicit PoseEstimator(PoseEstimatorSettings settings);
  ~PoseEstimator();

  void add_imu(double stamp, const Eigen::Quaterniond& orientation);
  void add_fix(double stamp, double latitude, double longitude, double altitude, double horizontal_sigma,
               double vertical_sigma);
  void add_pressure(double stamp, double pascal);
  // The scan matcher's increment (laser frame) since its previous scan, or none when the
  // match failed.
  void add_match(double stamp, std::optional<Eigen::Vector2d> increment);

  // A scan, for the ground it sees (under the match with the same stamp): its returns as
  // sensor::kept_points keeps them, every ray.
  void add_scan(const sensor::LaserScan& scan);

  // Poses of the results that became ready, oldest first; with `all`, of every result
  // (the input has ended).
  std::vector<EstimatedPose> take_ready(bool all = false);
  // The same poses again as they leave the fusion's window (FusionSettings::window s of
  // stamps later), their height and its sigma solved with every sample of that window: a
  // fixed-lag smoother's output, what a ground model is built from (docs/architecture.md).
  // Oldest first, each once. With `all` (the input has ended; after take_ready(true)), every
  // pose not settled yet. Callers take them, or they are kept. A height whose sigma the
  // window widened more than twice keeps its first solve (counted).
  std::vector<EstimatedPose> take_settled(bool all = false);
  uint64_t settled_as_first_solved() const { return settled_as_first_solved_; }

  // The altitude above the map origin that a pressure means.
  double barometric_height(double pascal) const;
  // A fix's position in the map frame (east, north, up from the origin).
  Eigen::Vector3d map_position(double latitude, double longitude, double altitude) const;
  const HeightFusion& fusion() const { return fusion_; }

 private:
  struct Match {
    double stamp;
    std::optional<Eigen::Vector2d> increment;
  };
  bool ready(const Match& match) const;
  EstimatedPose estimate(const Match& match);

  PoseEstimatorSettings settings_;
  struct Local;
  std::unique_ptr<Local> local_;  // GeographicLib's frame, kept out of this header
  HeightFusion fusion_;
  transforms::TransformSeries attitudes_{30.0}, positions_{30.0};
  Eigen::Vector3d position_sigma_ = Eigen::Vector3d::Zero();
  std::deque<Match> matches_;
  std::map<double, EstimatedPose> unsettled_;  // by stamp, until take_settled
  uint64_t settled_as_first_solved_ = 0;
  std::map<double, std::vector<Eigen::Vector3d>> scans_;  // points in the laser's frame by stamp, until
                                                          // the match is estimated
  double newest_scan_ = -INFINITY;                        // none yet: matches do not wait for scans
  double newest_pressure_ = -INFINITY;                    // likewise for pressures
  double newest_input_ = -INFINITY;
  std::optional<std::pair<double, Eigen::Quaterniond>> previous_;  // stamp and attitude of the last result
};

}  // namespace scanbus::pose_estimation
