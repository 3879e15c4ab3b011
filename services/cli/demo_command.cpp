// The main job: scan the built-in room through the real path (firmware simulator on a
// serial line, scanner_io as its own process, DDS) and report what came out.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cloud_files.hpp"
#include "commands.hpp"
#include "room_scan.hpp"

namespace scanbus::cli {

namespace {

struct DemoOptions {
  DdsOptions dds;
  std::string out = "out";
  bool json = false;
  double speed = 20;
};

int run_demo(const DemoOptions& options) {
  std::filesystem::create_directories(options.out);
  RoomScanOptions scan;
  scan.dds = options.dds;
  scan.speed = options.speed;
  scan.resolution = 1;  // the thesis's usual setting: 20 RPM
  scan.work_dir = options.out;
  scan.progress = !options.json && isatty(STDOUT_FILENO);
  const RoomScanResult result = run_room_scan(scan);

  Eigen::Vector3f low = result.points.front().position, high = low;
  for (const auto& point : result.points) {
    low = low.cwiseMin(point.position);
    high = high.cwiseMax(point.position);
  }
  const std::string pcd = options.out + "/scan.pcd", png = options.out + "/room_top.png";
  write_pcd(pcd, result.points);
  write_top_view_png(png, result.points, "scanbus demo: built-in room (thesis case 1), simulated scan");
  if (options.json) {
    std::cout << nlohmann::json{{"points", result.points.size()},
                                {"revolutions", result.revolutions},
                                {"extent_min", {low.x(), low.y(), low.z()}},
                                {"extent_max", {high.x(), high.y(), high.z()}},
                                {"files", {pcd, png}}}
              << "\n";
  } else {
    std::printf("scan of the built-in room: %zu points from %u revolutions\n", result.points.size(), result.revolutions);
    std::printf("cloud extent: x %.2f..%.2f m, y %.2f..%.2f m, z %.2f..%.2f m\n", low.x(), high.x(), low.y(), high.y(),
                low.z(), high.z());
    std::printf("wrote %s and %s\n", pcd.c_str(), png.c_str());
  }
  return 0;
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
