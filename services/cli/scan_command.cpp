#include <unistd.h>

#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "scanbus/child_process.hpp"
#include "scanbus/cloud_io/cloud_files.hpp"
#include "scanbus/launch/room_scan.hpp"
#include "scanbus/sim/scanner_sim.hpp"

namespace scanbus::cli {

namespace {

struct ScanOptions {
  launch::RoomScanOptions scan;
  DdsOptions dds;
  std::string out = "out/scan.pcd";
  bool json = false;
};

int run_scan(ScanOptions options) {
  const std::filesystem::path out(options.out);
  const std::string work_dir = out.has_parent_path() ? out.parent_path().string() : ".";
  std::filesystem::create_directories(work_dir);
  options.scan.progress = !options.json && isatty(STDOUT_FILENO);
  launch::System system({own_executable(), work_dir, options.dds.settings()});
  const launch::RoomScanResult result = launch::run_room_scan(system, options.scan);
  cloud_io::write_pcd(options.out, result.points);
  if (options.json) {
    std::cout << nlohmann::json{{"points", result.points.size()},
                                {"revolutions", result.revolutions},
                                {"file", options.out}}
              << "\n";
  } else {
    std::cout << "scan: " << result.points.size() << " points from " << result.revolutions << " revolutions, wrote "
              << options.out << "\n";
  }
  return 0;
}

}  // namespace

void add_scan_command(CLI::App& app, int& exit_code) {
  static ScanOptions options;
  auto* command = app.add_subcommand("scan", "Scan a simulated room: simulator on a pty, scanner_io, cloud to PCD");
  command->add_option("--room", options.scan.room_file, "Room YAML (default: the simulator's built-in room)")
      ->check(CLI::ExistingFile);
  command->add_option("--out", options.out, "PCD file for the whole scan (metres, frame scanner)");
  command->add_option("--speed", options.scan.speed, "Times real time")->check(CLI::Range(0.01, 1000.0));
  command->add_option("--scans", options.scan.scans, "Whole scans in a row (each interleaves its pitch, eq. 4.9)")
      ->check(CLI::Range(1, 100));
  command->add_option("--resolution", options.scan.resolution, "Table 4.2 setting: 0 = 12, 1 = 20, 2 = 28 RPM")
      ->check(CLI::Range(0, 2));
  command->add_option("--timeout", options.scan.timeout, "Give up after this many seconds")->check(CLI::PositiveNumber);
  command->add_flag("--json", options.json, "Print the result as one JSON object, no progress");
  add_dds_options(*command, options.dds);
  on_run(*command, exit_code, [] { return run_scan(options); });
}

void add_sim_command(CLI::App& app, int& exit_code) {
  static sim::ScannerSimOptions options;
  auto* command = app.add_subcommand("sim", "Simulators");
  command->require_subcommand(1);
  auto* scanner = command->add_subcommand("scanner", "The rotating scanner on a pseudo-terminal (prints 'pty PATH')");
  sim::add_scanner_sim_options(*scanner, options);
  scanner->callback([&exit_code] { exit_code = sim::run_scanner_sim(options); });
  add_mav_sim_command(*command, exit_code);
}

}  // namespace scanbus::cli
