#include "scanbus/ground_evaluation/flight_evaluation.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "scanbus/config.hpp"
#include "scanbus/pose_estimation/pose_estimator.hpp"
#include "scanbus/transforms/transform_buffer.hpp"

namespace scanbus::ground_evaluation {

namespace {

using sensor_replay::MavLog;
using sensor_replay::MavLogError;

// The fused cloud as an elevation grid, and each cell's height against the true ground
// averaged over the cell.
void grid_fused_cloud(const FlightEvaluationSettings& settings, FlightEvaluation& result) {
  const auto& fused = result.cloud[static_cast<int>(HeightSource::Fused)];
  if (fused.empty()) return;
  result.elevation = cloud_assembly::grid_elevation(fused, settings.elevation);
  if (!result.has_ground) return;
  std::vector<Eigen::Vector3f> cells;
  for (const auto& cell : result.elevation.filled_cells()) cells.push_back(cell.top);
  result.elevation_error =
      ground_model_error(cells, cell_average_truth(settings.true_ground, settings.elevation.cell_size));
}

}  // namespace

std::function<std::optional<double>(const Eigen::Vector2d&)> cell_average_truth(
    std::function<std::optional<double>(const Eigen::Vector2d&)> true_ground, double cell_size) {
  const int samples = std::max(5, static_cast<int>(std::ceil(cell_size / 0.1)));
  return [true_ground = std::move(true_ground), cell_size,
          samples](const Eigen::Vector2d& centre) -> std::optional<double> {
    double sum = 0;
    for (int i = 0; i < samples; ++i)
      for (int j = 0; j < samples; ++j) {
        const Eigen::Vector2d offset((i + 0.5) / samples - 0.5, (j + 0.5) / samples - 0.5);
        const auto height = true_ground(centre + cell_size * offset);
        if (!height) return std::nullopt;
        sum += *height;
      }
    return sum / (samples * samples);
  };
}

double HeightSeries::at(double stamp) const {
  const auto later = std::lower_bound(samples_.begin(), samples_.end(), stamp,
                                      [](const auto& sample, double t) { return sample.first < t; });
  if (later == samples_.begin()) return later->second;
  if (later == samples_.end()) return samples_.back().second;
  const auto& before = *std::prev(later);
  const double weight = (stamp - before.first) / (later->first - before.first);
  return (1 - weight) * before.second + weight * later->second;
}

double height_rmse(const std::vector<std::pair<double, double>>& stamped_heights, const HeightSeries& truth) {
  if (stamped_heights.empty()) return NAN;
  double squared = 0;
  for (const auto& [stamp, height] : stamped_heights) squared += std::pow(height - truth.at(stamp), 2);
  return std::sqrt(squared / static_cast<double>(stamped_heights.size()));
}

HeightSeries HeightSeries::truth_of(const sensor_replay::MavLog& log) {
  HeightSeries truth;
  for (const auto& record : log.truths) truth.add(record.stamp, record.position.z());
  return truth;
}

const char* mav_scan_matcher_config() {
  return
#include "mav_scan_matcher.inc"
      ;
}

scan_matcher::MatcherSettings mav_matcher_settings() {
  static const scan_matcher::MatcherSettings settings = scan_matcher::matcher_settings_from_config(
      Config::parse(mav_scan_matcher_config(), "config/mav/scan_matcher.yaml")
          .section("scan_matcher")
          .section("matcher"));
  return settings;
}

GroundModelError ground_model_error(const std::vector<Eigen::Vector3f>& cloud,
                                    const std::function<std::optional<double>(const Eigen::Vector2d&)>& true_ground) {
  GroundModelError error;
  std::vector<double> sizes;
  double squares = 0, sum = 0;
  // Normal equations of the planes z = a + b x + c y through the cloud and through the truth.
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d cloud_side = Eigen::Vector3d::Zero(), true_side = Eigen::Vector3d::Zero();
  for (const auto& p : cloud) {
    const std::optional<double> ground = true_ground(p.head<2>().cast<double>());
    if (!ground) continue;
    const double e = p.z() - *ground;
    squares += e * e, sum += e;
    sizes.push_back(std::abs(e));
    const Eigen::Vector3d row(1, p.x(), p.y());
    normal += row * row.transpose();
    cloud_side += row * p.z(), true_side += row * *ground;
  }
  error.points = sizes.size();
  if (sizes.empty()) return error;
  const Eigen::FullPivLU<Eigen::Matrix3d> planes(normal);
  if (planes.rank() == 3) {  // points along one line (a single pass) do not define a tilt
    error.slope = planes.solve(cloud_side).tail<2>();
    error.true_slope = planes.solve(true_side).tail<2>();
    constexpr double kLeastTilt = 0.01;  // dz per m: flatter, the relative error means nothing
    if (error.true_slope.norm() >= kLeastTilt)
      error.slope_error = (error.slope - error.true_slope).norm() / error.true_slope.norm();
  }
  const auto n = static_cast<double>(sizes.size());
  error.rmse = std::sqrt(squares / n);
  error.bias = sum / n;
  std::sort(sizes.begin(), sizes.end());
  error.median = sizes[sizes.size() / 2];
  error.p95 = sizes[std::min(sizes.size() - 1, static_cast<size_t>(0.95 * n))];
  return error;
}

namespace {

// The laser in base_link as the log's META laser_mount draws it.
Eigen::Isometry3d drawn_mount(const MavLog& log) {
  const auto& mount = log.meta_of("laser_mount", 6);
  return transforms::from_xyz_rpy({mount[0], mount[1], mount[2]}, {mount[3], mount[4], mount[5]});
}

}  // namespace

FlightEvaluation evaluate_flight(const MavLog& log, const FlightEvaluationSettings& settings,
                                 const std::function<void(size_t, size_t)>& progress) {
  const Eigen::Isometry3d mount = drawn_mount(log);
  const auto& origin = log.meta_of("origin", 3);
  if (log.truths.empty()) throw MavLogError("the log has no TRUTH records to score against");
  pose_estimation::PoseEstimatorSettings estimator_settings;
  estimator_settings.fusion = settings.fusion;
  estimator_settings.ground_clearance = settings.ground_clearance;
  estimator_settings.laser_in_body = pose_estimation::turned_in_scan_plane(mount, settings.scan_plane_rotation);
  estimator_settings.origin = {origin[0], origin[1], origin[2]};
  pose_estimation::PoseEstimator estimator(estimator_settings);
  scan_matcher::ScanMatcher matcher(settings.matcher);

  const HeightSeries truth = HeightSeries::truth_of(log);
  HeightSeries barometer, gps;
  for (const auto& record : log.baros) barometer.add(record.stamp, estimator.barometric_height(record.pressure));
  for (const auto& fix : log.fixes)
    gps.add(fix.stamp, estimator.map_position(fix.latitude, fix.longitude, fix.altitude).z());
  const int sources = log.fixes.empty() ? kHeightSources - 1 : kHeightSources;  // GPS last

  FlightEvaluation result;
  result.scans = log.lasers.size();
  std::map<double, size_t> scan_at;             // laser records waiting for their pose
  std::optional<double> integrated;             // the paper's height: first barometer + the changes
  std::vector<Eigen::Vector3f> at_true_height;  // the cloud a perfect height would give
  std::chrono::duration<double> fusion_time{0};
  std::map<double, std::pair<double, double>> immediate;  // stamp: the fused height and sigma as first solved
  const auto take_poses = [&](bool all) {
    const auto started = std::chrono::steady_clock::now();
    const auto ready = estimator.take_ready(all);
    for (const auto& pose : ready) immediate[pose.stamp] = {pose.position.z(), pose.position_sigma.z()};
    const auto poses = settings.settled_heights ? estimator.take_settled(all) : ready;  // the cloud's
    fusion_time += std::chrono::steady_clock::now() - started;
    for (const auto& pose : poses) {
      const auto found = scan_at.find(pose.stamp);
      if (found == scan_at.end()) continue;
      const double baro = barometer.at(pose.stamp);
      integrated = integrated ? *integrated + pose.height_change.value_or(0.0) : baro;
      const double heights[kHeightSources] = {baro, *integrated, pose.position.z(),
                                              log.fixes.empty() ? NAN : gps.at(pose.stamp)};
      const double true_height = truth.at(pose.stamp);
      const auto solved = immediate.find(pose.stamp);  // every pose is taken ready before it settles
      const auto [first, first_sigma] =
          solved == immediate.end() ? std::pair<double, double>{NAN, NAN} : solved->second;
      if (solved != immediate.end()) immediate.erase(immediate.begin(), std::next(solved));
      result.heights.push_back({pose.stamp,
                                true_height,
                                {heights[0], heights[1], heights[2], heights[3]},
                                pose.clearance.value_or(NAN),
                                pose.position_sigma.z(),
                                first,
                                first_sigma});
      const auto points = cloud_assembly::scan_points(log.lasers[found->second], settings.gating);
      const auto place = [&](double height, std::vector<Eigen::Vector3f>& cloud) {
        Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
        body.translation() = Eigen::Vector3d(pose.position.x(), pose.position.y(), height);
        body.linear() = pose.orientation.toRotationMatrix();
        const Eigen::Isometry3d map_T_laser = body * estimator_settings.laser_in_body;
        for (const auto& p : points) cloud.push_back((map_T_laser * p).cast<float>());
      };
      for (int source = 0; source < sources; ++source) place(heights[source], result.cloud[source]);
      if (settings.true_ground) place(true_height, at_true_height);
      ++result.poses;
      result.clearances += pose.clearance.has_value();
      scan_at.erase(found);
    }
  };

  const std::vector<sensor_replay::RecordRef> records = sensor_replay::records_in_time_order(log);
  for (size_t e = 0; e < records.size(); ++e) {
    const auto& record = records[e];
    switch (record.kind) {
      case sensor_replay::RecordKind::Imu:
        estimator.add_imu(record.stamp, log.imus[record.index].orientation);
        break;
      case sensor_replay::RecordKind::Gps: {
        const auto& fix = log.fixes[record.index];
        estimator.add_fix(fix.stamp, fix.latitude, fix.longitude, fix.altitude, fix.horizontal_sigma,
                          fix.vertical_sigma);
        break;
      }
      case sensor_replay::RecordKind::Baro:
        estimator.add_pressure(record.stamp, log.baros[record.index].pressure);
        break;
      case sensor_replay::RecordKind::Laser: {
        const auto& laser = log.lasers[record.index];
        estimator.add_scan(laser);
        const auto match = matcher.add_scan(laser);
        const bool ok = match.quality == scan_matcher::MatchQuality::Ok;
        result.matches_failed += !ok && match.quality != scan_matcher::MatchQuality::NoReference;
        std::optional<Eigen::Vector2d> increment;
        if (ok) increment = Eigen::Vector2d(match.increment.x, match.increment.y);
        scan_at[record.stamp] = record.index;
        estimator.add_match(record.stamp, increment);
        break;
      }
      case sensor_replay::RecordKind::Truth:
        continue;
    }
    take_poses(false);
    if (progress && e % 2000 == 0) progress(e, records.size());
  }
  take_poses(true);  // the log has ended: nothing more will come
  if (progress) progress(records.size(), records.size());

  for (int source = 0; source < kHeightSources; ++source) {  // GPS heights are NaN without fixes
    std::vector<std::pair<double, double>> stamped;
    for (const auto& h : result.heights) stamped.emplace_back(h.stamp, h.height[source]);
    result.height_rmse[source] = height_rmse(stamped, truth);
  }
  std::vector<std::pair<double, double>> solved;
  for (const auto& h : result.heights) solved.emplace_back(h.stamp, h.immediate);
  result.immediate_rmse = height_rmse(solved, truth);
  for (int k = 1; k <= 2; ++k) {
    const auto share = [&](auto error_within) {
      const auto within = std::count_if(result.heights.begin(), result.heights.end(), error_within);
      return result.heights.empty() ? NAN : static_cast<double>(within) / static_cast<double>(result.heights.size());
    };
    result.fused_within_sigma[k - 1] = share([k](const HeightSample& h) {
      return std::abs(h.height[static_cast<int>(HeightSource::Fused)] - h.truth) <= k * h.fused_sigma;
    });
    result.immediate_within_sigma[k - 1] =
        share([k](const HeightSample& h) { return std::abs(h.immediate - h.truth) <= k * h.immediate_sigma; });
  }
  result.changes_rejected = estimator.fusion().changes_rejected();
  result.ground_cells = estimator.fusion().ground_cells();
  result.fusion_ms_per_update = result.poses ? fusion_time.count() * 1000 / static_cast<double>(result.poses) : 0;
  result.has_ground = static_cast<bool>(settings.true_ground);
  if (result.has_ground) {
    for (int source = 0; source < sources; ++source)
      result.ground[source] = ground_model_error(result.cloud[source], settings.true_ground);
    result.ground_at_true_height = ground_model_error(at_true_height, settings.true_ground);
  }
  grid_fused_cloud(settings, result);
  const auto boxes = log.meta.find("boxes");
  result.has_boxes = boxes != log.meta.end() && boxes->second.size() >= 2;
  if (result.has_boxes) {
    for (int source = 0; source < sources; ++source)
      result.boxes[source] = evaluate_boxes(result.cloud[source], boxes->second[1], boxes->second[0], settings.boxes);
  }
  return result;
}

pose_estimation::ScanPlaneCalibration calibrate_scan_plane(const MavLog& log) {
  std::vector<pose_estimation::AttitudeSample> attitudes;
  attitudes.reserve(log.imus.size());
  for (const auto& imu : log.imus) attitudes.push_back({imu.stamp, imu.orientation});
  return pose_estimation::calibrate_scan_plane(log.lasers, attitudes, drawn_mount(log));
}

}  // namespace scanbus::ground_evaluation
