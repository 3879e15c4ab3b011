#include "scanbus/pose_estimation/pose_estimator.hpp"

#include <GeographicLib/LocalCartesian.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "scanbus/atmosphere.hpp"
#include "scanbus/pose_estimation/laser_height.hpp"
#include "scanbus/pose_estimation/scan_plane_calibration.hpp"
#include "scanbus/units.hpp"

namespace scanbus::pose_estimation {

PoseEstimatorSettings pose_estimator_settings_from_config(const Config& section) {
  PoseEstimatorSettings s;
  const auto origin = section.numbers("origin", 3);
  if (std::abs(origin[0]) > 90 || std::abs(origin[1]) > 180)
    section.fail("origin", "must be latitude, longitude in degrees");
  s.origin = {origin[0], origin[1], origin[2]};
  const Config mount = section.section("laser_mount");
  const auto xyz = mount.has("xyz") ? mount.numbers("xyz", 3) : std::vector<double>{0, 0, -0.1};
  const auto rpy = mount.has("rpy") ? mount.numbers("rpy", 3) : std::vector<double>{0, 90, 0};
  s.laser_in_body = turned_in_scan_plane(
      transforms::from_xyz_rpy({xyz[0], xyz[1], xyz[2]}, Eigen::Vector3d(rpy[0], rpy[1], rpy[2]) * kDegree),
      mount.number("scan_plane_rotation", 0.0, -10.0, 10.0) * kDegree);
  s.max_wait = section.number("max_wait", s.max_wait, 0.0, 10.0);
  s.ground_clearance = section.section("ground").flag("enabled", s.ground_clearance);
  s.gps_altitude = section.section("gps").flag("altitude", s.gps_altitude);
  const Config fusion = section.section("fusion");
  FusionSettings& f = s.fusion;
  f.window = fusion.number("window", f.window, 0.1, 600);
  f.baro_sigma = fusion.number("baro_sigma", f.baro_sigma, 1e-4, 100);
  f.baro_gate_time = fusion.number("baro_gate_time", f.baro_gate_time, 0, 3600);
  f.bias_random_walk = fusion.number("bias_random_walk", f.bias_random_walk, 1e-6, 100);
  f.bias_spacing = fusion.number("bias_spacing", f.bias_spacing, 0.01, 600);
  f.initial_bias_sigma = fusion.number("initial_bias_sigma", f.initial_bias_sigma, 1e-6, 1000);
  f.change_sigma = fusion.number("change_sigma", f.change_sigma, 1e-6, 10);
  f.change_loss = fusion.number("change_loss", f.change_loss, 1e-6, 10);
  f.change_gate = fusion.number("change_gate", f.change_gate, 1e-6, 100);
  f.gate_memory = fusion.number("gate_memory", f.gate_memory, 0, 600);
  f.height_walk = fusion.number("height_walk", f.height_walk, 1e-3, 100);
  f.solve_every = static_cast<int>(fusion.integer("solve_every", f.solve_every, 1, 1000));
  f.gps_wander_time = fusion.number("gps_wander_time", f.gps_wander_time, 0.1, 36000);
  f.cell_size = fusion.number("cell_size", f.cell_size, 0.05, 100);
  f.min_cell_returns = static_cast<int>(fusion.integer("min_cell_returns", f.min_cell_returns, 1, 100000));
  f.clearance_sigma = fusion.number("clearance_sigma", f.clearance_sigma, 1e-5, 10);
  f.clearance_loss = fusion.number("clearance_loss", f.clearance_loss, 1e-6, 100);
  f.clearance_gate = fusion.number("clearance_gate", f.clearance_gate, 1e-3, 100);
  f.ground_gradient_sigma = fusion.number("ground_gradient_sigma", f.ground_gradient_sigma, 1e-3, 1000);
  f.max_corners = static_cast<int>(fusion.integer("max_corners", f.max_corners, 4, 100000));
  f.origin_on_ground = fusion.flag("origin_on_ground", f.origin_on_ground);
  f.origin_sigma = fusion.number("origin_sigma", f.origin_sigma, 1e-4, 100);
  return s;
}

struct PoseEstimator::Local {
  GeographicLib::LocalCartesian frame;
};

PoseEstimator::PoseEstimator(PoseEstimatorSettings settings)
    : settings_(std::move(settings)),
      local_(
          new Local{GeographicLib::LocalCartesian(settings_.origin.x(), settings_.origin.y(), settings_.origin.z())}),
      fusion_(settings_.fusion) {}

PoseEstimator::~PoseEstimator() = default;

void PoseEstimator::add_imu(double stamp, const Eigen::Quaterniond& orientation) {
  Eigen::Isometry3d attitude = Eigen::Isometry3d::Identity();
  attitude.linear() = orientation.normalized().toRotationMatrix();
  attitudes_.add(stamp, attitude);
  newest_input_ = std::max(newest_input_, stamp);
}

void PoseEstimator::add_fix(double stamp, double latitude, double longitude, double altitude, double horizontal_sigma,
                            double vertical_sigma) {
  Eigen::Isometry3d position = Eigen::Isometry3d::Identity();
  position.translation() = map_position(latitude, longitude, altitude);
  positions_.add(stamp, position);
  position_sigma_ = Eigen::Vector3d(horizontal_sigma, horizontal_sigma, vertical_sigma);
  if (settings_.gps_altitude) fusion_.add_gps(stamp, position.translation().z(), vertical_sigma);
  newest_input_ = std::max(newest_input_, stamp);
}

Eigen::Vector3d PoseEstimator::map_position(double latitude, double longitude, double altitude) const {
  double east, north, up;
  local_->frame.Forward(latitude, longitude, altitude, east, north, up);
  return {east, north, up};
}

double PoseEstimator::barometric_height(double pascal) const {
  return altitude_at_pressure(pascal) - settings_.origin.z();
}

void PoseEstimator::add_pressure(double stamp, double pascal) {
  fusion_.add_barometer(stamp, barometric_height(pascal));
  newest_pressure_ = std::max(newest_pressure_, stamp);
  newest_input_ = std::max(newest_input_, stamp);
}

void PoseEstimator::add_match(double stamp, std::optional<Eigen::Vector2d> increment) {
  if (!matches_.empty() && stamp <= matches_.back().stamp) return;  // a repeat or out of order: nothing new
  if (previous_ && stamp <= previous_->first) return;
  matches_.push_back({stamp, increment});
  newest_input_ = std::max(newest_input_, stamp);
}

void PoseEstimator::add_scan(const sensor::LaserScan& scan) {
  if (!settings_.ground_clearance) return;
  const double stamp = scan.stamp;
  if (previous_ && stamp <= previous_->first) return;  // its match is gone already
  const sensor::RangeGate every_ray{0, std::numeric_limits<double>::infinity(), 2 * M_PI};
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector2d& p : sensor::kept_points(scan, every_ray)) points.emplace_back(p.x(), p.y(), 0.0);
  scans_[stamp] = std::move(points);
  // Bounded without matches: a match never waits longer than max_wait.
  scans_.erase(scans_.begin(), scans_.lower_bound(stamp - settings_.max_wait - 1));
  newest_scan_ = std::max(newest_scan_, stamp);
  newest_input_ = std::max(newest_input_, stamp);
}

bool PoseEstimator::ready(const Match& match) const {
  // The first height is the barometer's: the first result also waits for a pressure. Once
  // scans come, a match waits for its own; once pressures come, for one at or after its
  // stamp, so the fusion's node sees every pressure before it however late they arrive (the
  // heights are then the same on a loaded machine as on an idle one).
  const bool scan_in = std::isinf(newest_scan_) || newest_scan_ >= match.stamp;
  const bool pressure_in = std::isinf(newest_pressure_) || newest_pressure_ >= match.stamp;
  const bool covered = !attitudes_.empty() && attitudes_.newest() >= match.stamp && !positions_.empty() &&
                       positions_.newest() >= match.stamp && (previous_ || fusion_.has_barometer()) && scan_in &&
                       pressure_in;
  return covered || newest_input_ - match.stamp > settings_.max_wait;
}

EstimatedPose PoseEstimator::estimate(const Match& match) {
  EstimatedPose pose;
  pose.stamp = match.stamp;
  std::optional<Eigen::Quaterniond> attitude;
  if (!attitudes_.empty()) {
    attitude = Eigen::Quaterniond(attitudes_.at(match.stamp, INFINITY).linear());
    pose.has_attitude = attitudes_.outside_by(match.stamp) == 0;
    pose.orientation = *attitude;
  }
  std::optional<double> change;
  if (match.increment && attitude && previous_) {
    change = height_change(match.increment->x(), match.increment->y(), previous_->second, *attitude,
                           settings_.laser_in_body);
  }
  pose.height_change = change;
  if (!positions_.empty()) {
    pose.position.head<2>() = positions_.at(match.stamp, INFINITY).translation().head<2>();
    pose.has_position = positions_.outside_by(match.stamp) == 0;
  }
  // Without attitude and position the returns cannot be placed on the map.
  std::vector<GroundReturn> ground;
  const auto scan = scans_.find(match.stamp);
  if (scan != scans_.end() && attitude && pose.has_position) {
    ground = ground_returns(scan->second, *attitude, pose.position.head<2>(), settings_.laser_in_body);
    if (const auto median = median_return(ground)) pose.clearance = median->depth;
  }
  scans_.erase(scans_.begin(), scans_.upper_bound(match.stamp));
  const uint64_t rejected = fusion_.changes_rejected();
  pose.position.z() = fusion_.add_node(match.stamp, change, ground);
  pose.match_used = change.has_value() && fusion_.changes_rejected() == rejected;
  pose.position_sigma = position_sigma_;
  pose.position_sigma.z() = fusion_.height_sigma();
  if (attitude) previous_ = {match.stamp, *attitude};
  unsettled_.emplace(pose.stamp, pose);
  return pose;
}

std::vector<EstimatedPose> PoseEstimator::take_ready(bool all) {
  std::vector<EstimatedPose> poses;
  while (!matches_.empty() && (all || ready(matches_.front()))) {
    poses.push_back(estimate(matches_.front()));
    matches_.pop_front();
  }
  return poses;
}

std::optional<EstimatedPose> settled_pose(const EstimatedPose& first_solved, const SettledHeight& settled) {
  constexpr double kWidened = 2;
  if (!(settled.sigma <= kWidened * first_solved.position_sigma.z())) return std::nullopt;  // also NaN
  EstimatedPose pose = first_solved;
  pose.position.z() = settled.height;
  pose.position_sigma.z() = settled.sigma;
  return pose;
}

std::vector<EstimatedPose> PoseEstimator::take_settled(bool all) {
  std::vector<EstimatedPose> poses;
  for (const SettledHeight& node : fusion_.take_settled(all)) {
    const auto found = unsettled_.find(node.stamp);
    if (found == unsettled_.end()) continue;
    const std::optional<EstimatedPose> pose = settled_pose(found->second, node);
    poses.push_back(pose.value_or(found->second));
    settled_as_first_solved_ += !pose;
    unsettled_.erase(unsettled_.begin(), std::next(found));
  }
  return poses;
}

}  // namespace scanbus::pose_estimation
