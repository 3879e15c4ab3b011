#include "room_scan.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <optional>
#include <string>

#include "PointCloud2PubSubTypes.h"
#include "RoomMeasurementPubSubTypes.h"
#include "scanbus/child_process.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/service.hpp"

namespace scanbus::cli {

namespace {

constexpr unsigned kRevolutionsPerScan = 27;

}  // namespace

RoomScanResult run_room_scan(const RoomScanOptions& options) {
  StopSignal::install();
  mkdir(options.work_dir.c_str(), 0755);
  const std::string link = options.work_dir + "/scanner.tty";
  const std::string config = options.work_dir + "/scanner_io.yaml";
  std::ofstream(config) << "service:\n  health_period: 0.5\nscanner_io:\n  port: " << link
                        << "\n  resolution: " << options.resolution << "\n  scans: " << options.scans
                        << "\n  reconnect_min: 0.05\n  reconnect_max: 0.5\n";
  const std::string room_config = options.work_dir + "/room_measurement.yaml";
  std::ofstream(room_config) << "service:\n  health_period: 0.5\nroom_measurement:\n  scans: " << options.scans << "\n";
  // The services read their DDS settings from the environment: same domain and profile as ours.
  options.dds.export_to_children();

  Participant participant(options.dds.settings(), "scanbus/scan");
  std::mutex mutex;
  RoomScanResult result;
  int scans = 0;
  const unsigned total_revolutions = kRevolutionsPerScan * static_cast<unsigned>(options.scans);
  Reader<sensor_msgs::msg::PointCloud2PubSubType> revolution_reader(
      participant, topics::kScannerCloud, QosSettings{true, false, false, 50}, [&](const auto&, const auto&) {
        std::lock_guard<std::mutex> lock(mutex);
        ++result.revolutions;
        if (options.progress)
          std::printf("\rscanning: revolution %u of %u", result.revolutions, total_revolutions), std::fflush(stdout);
      });
  Reader<sensor_msgs::msg::PointCloud2PubSubType> scan_reader(
      participant, topics::kScannerScanCloud, [&](const auto& cloud, const auto&) {
        std::lock_guard<std::mutex> lock(mutex);
        const auto points = from_point_cloud2(cloud);
        result.points.insert(result.points.end(), points.begin(), points.end());
        ++scans;
      });
  Reader<scanbus::msg::RoomMeasurementPubSubType> room_reader(participant, topics::kRoomMeasurement,
                                                              [&](const auto& room, const auto&) {
                                                                std::lock_guard<std::mutex> lock(mutex);
                                                                result.room = room;
                                                              });

  ChildProcess scanner_io(own_executable(), {"run", "scanner_io", "--config", config},
                          options.work_dir + "/scanner_io.log");
  std::optional<ChildProcess> room_measurement;
  if (options.measure)
    room_measurement.emplace(own_executable(),
                             std::vector<std::string>{"run", "room_measurement", "--config", room_config},
                             options.work_dir + "/room_measurement.log");
  // Power the device on only once we hear the services: a revolution published before
  // discovery completes would never reach our (volatile) reader.
  const auto discovery_deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (revolution_reader.matched_writers() == 0 || scan_reader.matched_writers() == 0 ||
         (options.measure && room_reader.matched_writers() == 0)) {
    scanner_io.expect_running();
    if (room_measurement) room_measurement->expect_running();
    if (std::chrono::steady_clock::now() > discovery_deadline)
      throw std::runtime_error("the services did not appear on DDS within 20 s");
    if (StopSignal::wait_for(std::chrono::milliseconds(20))) throw std::runtime_error("interrupted");
  }
  std::vector<std::string> sim = {"sim", "scanner", "--link", link, "--speed", std::to_string(options.speed)};
  if (!options.room_file.empty()) sim.insert(sim.end(), {"--room", options.room_file});
  ChildProcess simulator(own_executable(), sim, options.work_dir + "/scanner_sim.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.timeout);
  std::optional<std::chrono::steady_clock::time_point> complete_at;
  while (!StopSignal::wait_for(std::chrono::milliseconds(100))) {
    simulator.expect_running();
    scanner_io.expect_running();
    if (room_measurement) room_measurement->expect_running();
    const auto now = std::chrono::steady_clock::now();
    if (now > deadline)
      throw std::runtime_error("no complete scan within " + std::to_string(static_cast<int>(options.timeout)) + " s");
    std::lock_guard<std::mutex> lock(mutex);
    if (scans < options.scans || (options.measure && !result.room)) continue;
    // Revolution clouds and the scan cloud come on separate topics, in no fixed order:
    // give the last revolution a moment to be counted.
    if (!complete_at) complete_at = now;
    if (result.revolutions >= total_revolutions || now - *complete_at > std::chrono::seconds(1)) break;
  }
  if (options.progress) std::printf("\n");
  std::lock_guard<std::mutex> lock(mutex);
  if (scans < options.scans || (options.measure && !result.room))
    throw std::runtime_error("interrupted before the scan completed");
  return result;
}

}  // namespace scanbus::cli
