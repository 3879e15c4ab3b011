#include "scanbus/launch/mav_flight.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "cloud_window_client.hpp"
#include "scanbus/atmosphere.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/ground_evaluation/flight_evaluation.hpp"
#include "scanbus/launch/system.hpp"
#include "scanbus/mav_sim/flight.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/service.hpp"

namespace scanbus::launch {

namespace {

// The services' configs for this flight: the matcher as 'scanbus eval mav' runs it, the
// pose estimator on the log's origin and laser mount.
// The replay outruns real time, so a loaded machine must neither lose samples on the way (every
// topic of the flight reliable with room for a backlog; the sensors' are best effort for a live
// sensor, the scan matches keep 10) nor drop scans in the assembly for a pose that comes late in
// stamp time (wait as long as transforms are cached), and the pose estimator waits for a late
// sensor a second of wall time (0.5 s of stamp time live; a replay's 8x made that 62 ms, and
// on a loaded machine poses went ahead without their IMU or GPS).
struct FlightConfigs {
  ServiceConfig scan_matcher, pose_estimation, cloud_assembly, sensor_replay;
};

std::vector<double> degrees(const std::vector<double>& radians) {
  std::vector<double> result;
  for (double angle : radians) result.push_back(angle * 180 / M_PI);
  return result;
}

constexpr double kInputEndedAfter = 1.5;  // s of wall time

FlightConfigs flight_configs(const sensor_replay::MavLog& log, const std::string& log_path, double rate) {
  ServiceConfig lossless;
  for (const char* topic : {topics::kScan.name, topics::kImu.name, topics::kFix.name, topics::kPressure.name,
                            topics::kScanMatch.name, topics::kPose.name, topics::kPoseSettled.name, topics::kTf.name})
    lossless.qos[topic] = QosSettings{true, false, false, 1000};
  FlightConfigs configs{lossless, lossless, lossless, lossless};
  const YAML::Node mav = YAML::Load(ground_evaluation::mav_scan_matcher_config());
  // A missing section would start the service on the defaults (constant velocity), silently.
  if (!mav["scan_matcher"].IsMap())
    throw std::runtime_error("config/mav/scan_matcher.yaml has no scan_matcher section");
  configs.scan_matcher.settings = mav["scan_matcher"];
  const auto& mount = log.meta_of("laser_mount", 6);
  YAML::Node& pose = configs.pose_estimation.settings;
  pose["origin"] = log.meta_of("origin", 3);
  pose["laser_mount"]["xyz"] = std::vector<double>(mount.begin(), mount.begin() + 3);
  pose["laser_mount"]["rpy"] = degrees(std::vector<double>(mount.begin() + 3, mount.end()));
  pose["max_wait"] = std::min(1.0 * rate, 10.0);  // a second of wall time, in stamp time
  // The flight's last 3 s settle when the input has ended: said sooner than the shipped 5 s.
  pose["input_ended_after"] = kInputEndedAfter;
  configs.cloud_assembly.settings["transform_timeout"] = 30;
  configs.sensor_replay.settings["log"] = log_path;
  configs.sensor_replay.settings["rate"] = rate;
  configs.sensor_replay.settings["wait_for_readers"] = 2;
  return configs;
}

}  // namespace

MavFlightResult run_mav_flight(System& system, const MavFlightOptions& options) {
  StopSignal::install();
  mav_sim::FlightSettings settings;
  settings.scenario = options.scenario;
  settings.duration = options.duration;
  const sensor_replay::MavLog log = mav_sim::simulate_flight(settings);
  const std::string log_path = system.path("flight.mavlog");
  sensor_replay::write_mav_log(log_path, log);
  const FlightConfigs configs = flight_configs(log, log_path, options.rate);

  Participant participant(system.dds(), "scanbus/demo");
  std::mutex mutex;
  std::vector<std::pair<double, double>> heights;  // stamp, fused height as it settled (what places the scans)
  Reader<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType> poses(
      participant, topics::kPoseSettled, QosSettings{true, false, false, 1000}, [&](const auto& pose, const auto&) {
        std::lock_guard<std::mutex> lock(mutex);
        heights.emplace_back(to_seconds(pose.header().stamp()), pose.pose().pose().position().z());
      });
  // cloud_assembly can lag behind the poses under load: the cloud is asked for once it has
  // handled every scan, or a window asked for early misses the flight's last scans.
  std::atomic<uint64_t> scans_handled{0};
  Reader<scanbus::msg::HealthPubSubType> health(participant, topics::kHealth, [&](const auto& sample, const auto&) {
    if (sample.service() != "cloud_assembly") return;
    uint64_t handled = 0;
    for (const auto& counter : sample.counters())
      if (counter.name() == "scans_assembled" || counter.name() == "scans_dropped" ||
          counter.name() == "scans_rejected")
        handled += counter.value();
    scans_handled = handled;
  });
  system.start("scan_matcher", configs.scan_matcher);
  system.start("pose_estimation", configs.pose_estimation);
  system.start("cloud_assembly", configs.cloud_assembly);
  system.wait_until([&] { return poses.matched_writers() > 0; }, 20, "pose_estimation did not appear on DDS");
  ChildProcess& replay = system.start("sensor_replay", configs.sensor_replay, Lifetime::RunsToEnd);
  const auto received = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return heights.size();
  };
  std::optional<std::chrono::steady_clock::time_point> ended;
  system.wait_until(
      [&] {
        if (options.progress)
          std::printf("\rMAV flight: pose %zu of %zu", received(), log.lasers.size()), std::fflush(stdout);
        // The last poses settle once the input has ended, and may still be on their way; the
        // replay stays a while after its end (linger_for_lagging_readers).
        if (received() >= log.lasers.size()) return true;
        if (!replay.exited()) return false;
        if (!ended) ended = std::chrono::steady_clock::now();
        return std::chrono::steady_clock::now() - *ended > std::chrono::duration<double>(kInputEndedAfter + 2);
      },
      options.timeout, "the flight's replay did not end", std::chrono::milliseconds(200));
  if (options.progress) std::printf("\n");
  // Past 10 s the window is asked for all the same, with what cloud_assembly has.
  system.wait_for([&] { return scans_handled >= log.lasers.size(); }, 10, std::chrono::milliseconds(50));
  std::string problem;
  const auto cloud =
      cloud_assembly::request_window_cloud(participant, log.lasers.front().stamp, log.lasers.back().stamp, 30, problem);
  if (!cloud) throw std::runtime_error("the flight's cloud: " + problem);
  system.check();  // a replay that failed after the last pose (it may still be lingering: fine)

  MavFlightResult result;
  result.scans = log.lasers.size();
  std::lock_guard<std::mutex> lock(mutex);
  result.poses = heights.size();
  const auto truth = ground_evaluation::HeightSeries::truth_of(log);
  result.fused_rmse = ground_evaluation::height_rmse(heights, truth);
  const double origin_altitude = log.meta_of("origin", 3)[2];
  std::vector<std::pair<double, double>> barometer;
  for (const auto& baro : log.baros)
    barometer.emplace_back(baro.stamp, altitude_at_pressure(baro.pressure) - origin_altitude);
  result.barometer_rmse = ground_evaluation::height_rmse(barometer, truth);
  for (const auto& point : from_point_cloud2(*cloud)) result.cloud.push_back(point.position);
  if (const auto box = log.meta.find("boxes"); box != log.meta.end() && box->second.size() == 3) {
    result.box_size = Eigen::Vector3d(box->second[0], box->second[1], box->second[2]);
    result.boxes = ground_evaluation::evaluate_boxes(result.cloud, result.box_size.y(), result.box_size.x());
  }
  return result;
}

}  // namespace scanbus::launch
