#include "scanbus/launch/room_scan.hpp"

#include <cstdio>
#include <mutex>
#include <optional>
#include <string>

#include "scanbus/launch/system.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/service.hpp"
#include "scanbus_msgs/PointCloud2PubSubTypes.h"
#include "scanbus_msgs/RoomMeasurementPubSubTypes.h"

namespace scanbus::launch {

namespace {

constexpr unsigned kRevolutionsPerScan = 27;

// Health every half second (1 s by default): a scan takes tens of seconds, and `scanbus health`
// beside it shows a service's state soon after it changes.
ServiceConfig service_config() {
  ServiceConfig config;
  config.health_period = 0.5;
  return config;
}

}  // namespace

RoomScanResult run_room_scan(System& system, const RoomScanOptions& options) {
  StopSignal::install();
  const std::string link = system.path("scanner.tty");
  ServiceConfig scanner_io = service_config();
  scanner_io.settings["port"] = link;
  scanner_io.settings["resolution"] = options.resolution;
  scanner_io.settings["scans"] = options.scans;
  // The simulator's pty appears once it starts: look for it often.
  scanner_io.settings["reconnect_min"] = 0.05;
  scanner_io.settings["reconnect_max"] = 0.5;
  ServiceConfig room_measurement = service_config();
  room_measurement.settings["scans"] = options.scans;

  Participant participant(system.dds(), "scanbus/scan");
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

  system.start("scanner_io", scanner_io);
  if (options.measure) system.start("room_measurement", room_measurement);
  // Power the device on only once we hear the services: a revolution published before
  // discovery completes would never reach our (volatile) reader.
  system.wait_until(
      [&] {
        return revolution_reader.matched_writers() > 0 && scan_reader.matched_writers() > 0 &&
               (!options.measure || room_reader.matched_writers() > 0);
      },
      20, "the services did not appear on DDS");
  std::vector<std::string> simulator = {"sim", "scanner", "--link", link, "--speed", std::to_string(options.speed)};
  if (!options.room_file.empty()) simulator.insert(simulator.end(), {"--room", options.room_file});
  system.start_command("scanner_sim", simulator);
  std::optional<std::chrono::steady_clock::time_point> complete_at;
  system.wait_until(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        if (scans < options.scans || (options.measure && !result.room)) return false;
        // Revolution clouds and the scan cloud come on separate topics, in no fixed order:
        // give the last revolution a moment to be counted.
        const auto now = std::chrono::steady_clock::now();
        if (!complete_at) complete_at = now;
        return result.revolutions >= total_revolutions || now - *complete_at > std::chrono::seconds(1);
      },
      options.timeout, "no complete scan", std::chrono::milliseconds(100));
  if (options.progress) std::printf("\n");
  std::lock_guard<std::mutex> lock(mutex);
  return result;
}

}  // namespace scanbus::launch
