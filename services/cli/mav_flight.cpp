#include "mav_flight.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>

#include "cloud_request.hpp"
#include "scanbus/atmosphere.hpp"
#include "scanbus/child_process.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/ground_evaluation/flight_evaluation.hpp"
#include "scanbus/mav_sim/flight.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/service.hpp"

namespace scanbus::cli {

namespace {

// The services' configs for this flight: the matcher as 'scanbus eval mav' runs it, the
// pose estimator on the log's origin and laser mount.
// The replay outruns real time, so a loaded machine must neither lose samples on the way (every
// topic of the flight reliable with room for a backlog; the sensors' are best effort for a live
// sensor, the scan matches keep 10) nor drop scans in the assembly for a pose that comes late in
// stamp time (wait as long as transforms are cached), and the pose estimator waits for a late
// sensor a second of wall time (0.5 s of stamp time live; a replay's 8x made that 62 ms, and
// on a loaded machine poses went ahead without their IMU or GPS).
void write_configs(const std::string& dir, const sensor_replay::MavLog& log, const std::string& log_path, double rate) {
  std::string lossless = "qos:\n";
  for (const char* topic : {topics::kScan.name, topics::kImu.name, topics::kFix.name, topics::kPressure.name,
                            topics::kScanMatch.name, topics::kPose.name, topics::kTf.name})
    lossless += std::string("  ") + topic + ": {reliability: reliable, depth: 1000}\n";
  const auto matcher = ground_evaluation::mav_matcher_settings();
  std::ofstream(dir + "/scan_matcher.yaml")
      << lossless << "scan_matcher:\n  matcher:\n    opening: " << matcher.opening * 180 / M_PI
      << "\n    max_correspondence: " << matcher.max_correspondence << "\n";
  const auto& origin = log.meta_of("origin", 3);
  const auto& mount = log.meta_of("laser_mount", 6);
  std::ofstream pose(dir + "/pose_estimation.yaml");
  pose.precision(10);
  pose << lossless << "pose_estimation:\n  origin: [" << origin[0] << ", " << origin[1] << ", " << origin[2] << "]\n"
       << "  laser_mount:\n    xyz: [" << mount[0] << ", " << mount[1] << ", " << mount[2] << "]\n    rpy: ["
       << mount[3] * 180 / M_PI << ", " << mount[4] * 180 / M_PI << ", " << mount[5] * 180 / M_PI << "]\n"
       << "  max_wait: " << std::min(1.0 * rate, 10.0) << "\n";  // a second of wall time, in stamp time
  std::ofstream(dir + "/cloud_assembly.yaml") << lossless << "cloud_assembly:\n  transform_timeout: 30\n";
  std::ofstream(dir + "/sensor_replay.yaml")
      << lossless << "sensor_replay:\n  log: " << log_path << "\n  rate: " << rate << "\n  wait_for_readers: 2\n";
}

}  // namespace

MavFlightResult run_mav_flight(const MavFlightOptions& options) {
  StopSignal::install();
  std::filesystem::create_directories(options.work_dir);
  mav_sim::FlightSettings settings;
  settings.scenario = options.scenario;
  settings.duration = options.duration;
  const sensor_replay::MavLog log = mav_sim::simulate_flight(settings);
  const std::string log_path = options.work_dir + "/flight.mavlog";
  sensor_replay::write_mav_log(log_path, log);
  write_configs(options.work_dir, log, log_path, options.rate);
  options.dds.export_to_children();

  Participant participant(options.dds.settings(), "scanbus/demo");
  std::mutex mutex;
  std::vector<std::pair<double, double>> heights;  // stamp, fused height
  Reader<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType> poses(
      participant, topics::kPose, QosSettings{true, false, false, 1000}, [&](const auto& pose, const auto&) {
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
  std::vector<std::unique_ptr<ChildProcess>> services;
  for (const char* name : {"scan_matcher", "pose_estimation", "cloud_assembly"}) {
    services.push_back(std::make_unique<ChildProcess>(
        own_executable(), std::vector<std::string>{"run", name, "--config", options.work_dir + "/" + name + ".yaml"},
        options.work_dir + "/" + name + ".log"));
  }
  const auto check_services = [&] {
    for (auto& service : services) service->expect_running();
  };
  const auto discovery_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (poses.matched_writers() == 0) {
    check_services();
    if (std::chrono::steady_clock::now() > discovery_deadline)
      throw std::runtime_error("pose_estimation did not appear on DDS within 20 s");
    if (StopSignal::wait_for(std::chrono::milliseconds(20))) throw std::runtime_error("interrupted");
  }
  ChildProcess replay(own_executable(), {"run", "sensor_replay", "--config", options.work_dir + "/sensor_replay.yaml"},
                      options.work_dir + "/sensor_replay.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout);
  std::optional<std::chrono::steady_clock::time_point> ended;
  while (true) {
    if (StopSignal::wait_for(std::chrono::milliseconds(200))) throw std::runtime_error("interrupted");
    check_services();
    if (std::chrono::steady_clock::now() > deadline)
      throw std::runtime_error("the flight's replay did not end in time");
    size_t received;
    {
      std::lock_guard<std::mutex> lock(mutex);
      received = heights.size();
    }
    if (options.progress)
      std::printf("\rMAV flight: pose %zu of %zu", received, log.lasers.size()), std::fflush(stdout);
    if (auto status = replay.exited()) {
      if (*status != 0)
        throw std::runtime_error("sensor_replay exited with status " + std::to_string(*status) + " (see " +
                                 replay.log_path() + ")");
      if (!ended) ended = std::chrono::steady_clock::now();
      // The last poses may still be on their way.
      if (received >= log.lasers.size() || std::chrono::steady_clock::now() - *ended > std::chrono::seconds(2)) break;
    }
  }
  if (options.progress) std::printf("\n");
  const auto assembled_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (scans_handled < log.lasers.size() && std::chrono::steady_clock::now() < assembled_deadline) {
    check_services();
    if (StopSignal::wait_for(std::chrono::milliseconds(50))) throw std::runtime_error("interrupted");
  }
  std::string problem;
  const auto cloud = request_window_cloud(participant, log.lasers.front().stamp, log.lasers.back().stamp, 30, problem);
  if (!cloud) throw std::runtime_error("the flight's cloud: " + problem);

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

}  // namespace scanbus::cli
