// The main job: scan the built-in room through the real path (firmware simulator on a
// serial line, scanner_io and room_measurement as their own processes, DDS) and report
// the room that came out.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <vector>

#include "commands.hpp"
#include "room_report.hpp"
#include "scanbus/child_process.hpp"
#include "scanbus/cloud_io/cloud_files.hpp"
#include "scanbus/launch/mav_flight.hpp"
#include "scanbus/launch/room_scan.hpp"
#include "scanbus/plot/cloud_picture.hpp"
#include "scanbus/room_measurement/room_message.hpp"
#include "scanbus/room_plan/floor_plan.hpp"
#include "scanbus/service.hpp"

namespace scanbus::cli {

namespace {

struct DemoOptions {
  DdsOptions dds;
  std::string out = "out";
  bool json = false;
  double speed = 40;
  double mav_rate = 8;
  bool mav = true;
  int foxglove_port = 0;  // > 0: the Foxglove bridge on this port, and the services kept until Ctrl-C
};

// The MAV paper's scenario IV through the services: poses and cloud back over DDS.
launch::MavFlightResult fly_mav(launch::System& system, const DemoOptions& options) {
  launch::MavFlightOptions flight;
  flight.rate = options.mav_rate;
  flight.progress = !options.json && isatty(STDOUT_FILENO);
  return launch::run_mav_flight(system, flight);
}

// The bridge comes first, so a Foxglove opened now shows the scan and the flight live.
std::string start_foxglove_bridge(launch::System& system, int port) {
  launch::ServiceConfig config;
  config.settings["port"] = port;
  system.start("foxglove_bridge", config);
  return "ws://127.0.0.1:" + std::to_string(port);
}

// After the results: the services' last samples stay on the bus (latched) for Foxglove.
// Said on stderr under --json, whose stdout is the one JSON object.
void keep_running(const std::vector<launch::System*>& systems, const std::string& address, bool json) {
  std::fprintf(json ? stderr : stdout, "the services keep running for Foxglove at %s until Ctrl-C\n", address.c_str());
  std::fflush(json ? stderr : stdout);
  while (!StopSignal::wait_for(std::chrono::milliseconds(200)))
    for (auto* system : systems) system->check();
}

nlohmann::json mav_json(const launch::MavFlightResult& mav, const std::vector<std::string>& files) {
  nlohmann::json json{{"scans", mav.scans},
                      {"poses", mav.poses},
                      {"height_rmse_m", {{"fused", mav.fused_rmse}, {"barometer", mav.barometer_rmse}}},
                      {"boxes_ok", mav.boxes.ok},
                      {"files", files}};
  if (mav.boxes.ok)
    json["boxes_performance_percent"] = mav.boxes.mean_performance_percent;
  else
    json["boxes_message"] = mav.boxes.message;
  return json;
}

int run_demo(const DemoOptions& options) {
  std::filesystem::create_directories(options.out);
  StopSignal::install();
  // Without --foxglove the room's processes end with the room (the flight has the machine).
  std::optional<launch::System> room_system;
  room_system.emplace(launch::SystemSettings{own_executable(), options.out, options.dds.settings()});
  std::string foxglove;
  if (options.foxglove_port > 0) {
    foxglove = start_foxglove_bridge(*room_system, options.foxglove_port);
    if (!options.json)
      std::printf("Foxglove: open %s (Open connection, Foxglove WebSocket; layout: docs/foxglove_layout.json)\n",
                  foxglove.c_str()),
          std::fflush(stdout);
  }
  launch::RoomScanOptions scan;
  scan.speed = options.speed;
  scan.resolution = 1;  // the thesis's usual setting: 20 RPM
  scan.scans = 3;       // interleaved by eq. 4.9: one scan is too sparse for the histogram filter
  scan.measure = true;
  scan.progress = !options.json && isatty(STDOUT_FILENO);
  const launch::RoomScanResult result = launch::run_room_scan(*room_system, scan);
  if (foxglove.empty()) room_system.reset();

  Eigen::Vector3f low = result.points.front().position, high = low;
  for (const auto& point : result.points) {
    low = low.cwiseMin(point.position);
    high = high.cwiseMax(point.position);
  }
  const room_measurement::RoomResult room = room_measurement::from_message(*result.room);
  const std::string pcd = options.out + "/scan.pcd", png = options.out + "/room_top.png",
                    plan = options.out + "/floor_plan.png", drawing = options.out + "/floor_plan.dxf";
  cloud_io::write_pcd(pcd, result.points);
  plot::write_cloud_picture(png, result.points, "scanbus demo: built-in room (thesis case 1), simulated scan",
                            plot::CloudView::Top, true);
  std::vector<Eigen::Vector3f> background;
  for (const auto& point : result.points) background.push_back(point.position);
  const std::string plan_title = "scanbus demo: built-in room (thesis case 1, 5.47 m x 3.48 m)";
  room_plan::write_floor_plan(plan, room, plan_title, background);
  room_plan::write_floor_plan(drawing, room, plan_title);
  if (!options.json) {
    std::printf("scan of the built-in room: %zu points from %u revolutions\n", result.points.size(),
                result.revolutions);
    std::printf("%s", room_text(room).c_str());
    std::printf("wrote %s, %s, %s and %s\n", pcd.c_str(), png.c_str(), plan.c_str(), drawing.c_str());
  }
  nlohmann::json json{{"points", result.points.size()},
                      {"revolutions", result.revolutions},
                      {"extent_min", {low.x(), low.y(), low.z()}},
                      {"extent_max", {high.x(), high.y(), high.z()}},
                      {"room", room_json(room)},
                      {"files", {pcd, png, plan, drawing}}};
  bool mav_ok = true;
  std::optional<launch::System> mav_system;
  if (options.mav) {
    mav_system.emplace(launch::SystemSettings{own_executable(), options.out + "/mav", options.dds.settings()});
    const launch::MavFlightResult mav = fly_mav(*mav_system, options);
    std::vector<CloudPoint> points;
    for (const auto& p : mav.cloud) points.push_back({p, 0.0f});
    const std::string mav_pcd = options.out + "/mav_cloud.pcd", top = options.out + "/mav_top.png",
                      side = options.out + "/mav_side.png";
    cloud_io::write_pcd(mav_pcd, points);
    const std::string title = "scanbus demo: MAV scenario IV, ground cloud from the fused poses";
    plot::write_cloud_picture(top, points, title, plot::CloudView::Top, false);
    plot::write_cloud_picture(side, points, title, plot::CloudView::Side, false);
    mav_ok = mav.boxes.ok;
    json["mav"] = mav_json(mav, {mav_pcd, top, side});
    if (!options.json) {
      std::printf(
          "MAV scenario IV (two %.1f x %.1f x %.1f m boxes), %.0f s replayed at %gx through the services: %zu poses of "
          "%zu scans\n",
          mav.box_size.x(), mav.box_size.y(), mav.box_size.z(), mav.scans / 30.0, options.mav_rate, mav.poses,
          mav.scans);
      std::printf("height RMSE against the truth: fused %.3f m, barometer alone %.3f m\n", mav.fused_rmse,
                  mav.barometer_rmse);
      if (mav.boxes.ok) {
        for (const auto& box : mav.boxes.boxes)
          std::printf("box at (%.2f, %.2f): %.3f x %.3f m\n", box.centre.x(), box.centre.y(), box.length, box.width);
        std::printf("boxes P = %.2f %% (the paper: 71.54 %% without, 91.56 %% with its scan matcher)\n",
                    mav.boxes.mean_performance_percent);
      } else {
        std::printf("boxes not measured: %s\n", mav.boxes.message.c_str());
      }
      std::printf("wrote %s, %s and %s\n", mav_pcd.c_str(), top.c_str(), side.c_str());
    }
  }
  if (!foxglove.empty()) json["foxglove"] = foxglove;
  if (options.json) std::cout << json << std::endl;
  if (!foxglove.empty()) {
    std::vector<launch::System*> systems{&*room_system};
    if (mav_system) systems.push_back(&*mav_system);
    keep_running(systems, foxglove, options.json);
  }
  return room.status == room_measurement::RoomStatus::Ok && mav_ok ? 0 : 1;
}

}  // namespace

void add_demo_command(CLI::App& app, int& exit_code) {
  static DemoOptions options;
  auto* command = app.add_subcommand("demo",
                                     "Scan the built-in room and fly the MAV's scenario IV through the services; "
                                     "write the results");
  command->add_option("--out", options.out, "Folder for the cloud, the picture and the processes' logs");
  command->add_option("--speed", options.speed, "Simulated scanner's speed, times real time")
      ->check(CLI::Range(0.01, 1000.0));
  command->add_option("--mav-rate", options.mav_rate, "MAV flight's replay, times real time")
      ->check(CLI::Range(0.1, 100.0));
  command->add_flag("!--no-mav", options.mav, "Only the room, not the MAV flight");
  command
      ->add_option("--foxglove", options.foxglove_port,
                   "Also run the Foxglove bridge on this port of 127.0.0.1 (8765 when given without a value), "
                   "and keep the services running after the result until Ctrl-C")
      ->expected(0, 1)
      ->default_str("8765")
      ->check(CLI::Range(1, 65535));
  command->add_flag("--json", options.json, "Print the result as one JSON object, no progress");
  add_dds_options(*command, options.dds);
  on_run(*command, exit_code, [] { return run_demo(options); });
}

}  // namespace scanbus::cli
