// The main job: scan the built-in room through the real path (firmware simulator on a
// serial line, scanner_io and room_measurement as their own processes, DDS) and report
// the room that came out.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cloud_files.hpp"
#include "commands.hpp"
#include "floor_plan.hpp"
#include "room_report.hpp"
#include "room_scan.hpp"

namespace scanbus::cli {

namespace {

struct DemoOptions {
  DdsOptions dds;
  std::string out = "out";
  bool json = false;
  double speed = 40;
};

int run_demo(const DemoOptions& options) {
  std::filesystem::create_directories(options.out);
  RoomScanOptions scan;
  scan.dds = options.dds;
  scan.speed = options.speed;
  scan.resolution = 1;  // the thesis's usual setting: 20 RPM
  scan.scans = 3;       // interleaved by eq. 4.9: one scan is too sparse for the histogram filter
  scan.measure = true;
  scan.work_dir = options.out;
  scan.progress = !options.json && isatty(STDOUT_FILENO);
  const RoomScanResult result = run_room_scan(scan);

  Eigen::Vector3f low = result.points.front().position, high = low;
  for (const auto& point : result.points) {
    low = low.cwiseMin(point.position);
    high = high.cwiseMax(point.position);
  }
  const room_measurement::RoomResult room = room_from_message(*result.room);
  const std::string pcd = options.out + "/scan.pcd", png = options.out + "/room_top.png",
                    plan = options.out + "/floor_plan.png";
  write_pcd(pcd, result.points);
  write_cloud_png(png, result.points, "scanbus demo: built-in room (thesis case 1), simulated scan", CloudView::Top, true);
  std::vector<Eigen::Vector3f> background;
  for (const auto& point : result.points) background.push_back(point.position);
  write_floor_plan(plan, room, "scanbus demo: built-in room (thesis case 1, 5.47 m x 3.48 m)", background);
  if (options.json) {
    std::cout << nlohmann::json{{"points", result.points.size()},
                                {"revolutions", result.revolutions},
                                {"extent_min", {low.x(), low.y(), low.z()}},
                                {"extent_max", {high.x(), high.y(), high.z()}},
                                {"room", room_json(room)},
                                {"files", {pcd, png, plan}}}
              << "\n";
  } else {
    std::printf("scan of the built-in room: %zu points from %u revolutions\n", result.points.size(), result.revolutions);
    std::printf("%s", room_text(room).c_str());
    std::printf("wrote %s, %s and %s\n", pcd.c_str(), png.c_str(), plan.c_str());
  }
  return room.status == room_measurement::RoomStatus::Ok ? 0 : 1;
}

}  // namespace

void add_demo_command(CLI::App& app, int& exit_code) {
  static DemoOptions options;
  auto* command = app.add_subcommand("demo", "Scan the built-in room through the services and write the result");
  command->add_option("--out", options.out, "Folder for the cloud, the picture and the processes' logs");
  command->add_option("--speed", options.speed, "Simulated scanner's speed, times real time")->check(CLI::Range(0.01, 1000.0));
  command->add_flag("--json", options.json, "Print the result as one JSON object, no progress");
  add_dds_options(*command, options.dds);
  on_run(*command, exit_code, [] { return run_demo(options); });
}

}  // namespace scanbus::cli
