#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <vector>

#include "commands.hpp"
#include "room_measurement_node.hpp"
#include "room_report.hpp"
#include "scanbus/cloud_io/cloud_files.hpp"
#include "scanbus/room_measurement/device_calibration.hpp"
#include "scanbus/room_plan/floor_plan.hpp"

namespace scanbus::cli {

namespace {

struct RoomOptions {
  std::string file;
  std::string unit = "m";
  std::string config;
  bool json = false;
  std::string plan;
};

// Exit codes: 0 measured, 1 could not measure, 2 bad input.
int run_measure(const RoomOptions& options) {
  const auto loaded = room_settings_for(options.config, "room measure");
  if (!loaded) return 2;
  const room_measurement::RoomSettings& settings = *loaded;
  const double scale = cloud_io::metres_per_unit(options.unit);
  room_measurement::RoomResult room;
  try {
    room = room_measurement::measure_room(cloud_io::read_cloud(options.file, scale), settings);
  } catch (const cloud_io::CloudFileError& e) {
    if (options.json) {
      std::cout << nlohmann::json{{"status", "input_error"}, {"message", e.what()}} << "\n";
    } else {
      std::cerr << "scanbus room measure: " << e.what() << "\n";
    }
    return 2;
  }
  std::cout << (options.json ? room_json(room).dump() + "\n" : room_text(room)) << std::flush;
  // After the result: a plan that cannot be written loses no measurement.
  if (!options.plan.empty()) room_plan::write_floor_plan(options.plan, room, options.file);
  return room.status == room_measurement::RoomStatus::Ok ? 0 : 1;
}

struct CalibrateOptions {
  std::vector<std::string> files;
  std::string unit = "m";
  std::string config;
  bool json = false;
};

// The calibration as the config lines that apply it.
std::string calibration_yaml(const room_measurement::AdjustmentSettings& a, size_t scans) {
  char text[640];
  std::snprintf(text, sizeof text,
                "room_measurement:\n  adjustment:  # this unit, calibrated on %zu scans\n"
                "    range_bias: %.5f\n    lever_arm: %.5f\n    pitch_offset: %.4f\n"
                "    range_bias_prior: %.5f\n    lever_arm_prior: %.5f\n    pitch_error_prior: %.4f\n",
                scans, a.calibrated_range_bias, a.calibrated_lever_arm, a.calibrated_pitch_offset_deg,
                a.range_bias_prior, a.lever_arm_prior, a.pitch_error_prior_deg);
  return text;
}

// Exit codes: 0 calibrated, 1 too few scans with the device terms estimated and agreeing, 2 bad input
// (a file it cannot read or a config error; the other files still calibrate).
int run_calibrate(const CalibrateOptions& options) {
  auto loaded = room_settings_for(options.config, "room calibrate");
  if (!loaded) return 2;
  room_measurement::RoomSettings& settings = *loaded;
  const double scale = cloud_io::metres_per_unit(options.unit);
  std::vector<room_measurement::DeviceEstimate> scans;
  nlohmann::json files = nlohmann::json::array();
  bool bad_file = false;
  for (const auto& file : options.files) {
    room_measurement::RoomResult room;
    try {
      room = room_measurement::measure_room(cloud_io::read_cloud(file, scale), settings);
    } catch (const std::exception& e) {  // the other scans still count
      bad_file = true;
      files.push_back({{"file", file}, {"status", "input_error"}, {"message", e.what()}});
      if (!options.json) std::cerr << "scanbus room calibrate: " << e.what() << "\n";
      continue;
    }
    const char* device = room_measurement::device_state_name(room.device.state);
    files.push_back({{"file", file}, {"status", room_measurement::status_name(room.status)}, {"device", device}});
    if (!options.json)
      std::cout << file << ": " << room_measurement::status_name(room.status) << ", device " << device << "\n";
    if (room.status == room_measurement::RoomStatus::Ok) scans.push_back(room.device);
  }
  room_measurement::UnitCalibration calibration;
  try {
    calibration = room_measurement::calibrate_unit(scans);
  } catch (const std::invalid_argument& e) {
    if (options.json) {
      std::cout << nlohmann::json{{"files", files}, {"status", "too_few_scans"}, {"message", e.what()}} << "\n";
    } else {
      std::cerr << "scanbus room calibrate: " << e.what() << "\n";
    }
    return bad_file ? 2 : 1;
  }
  room_measurement::apply_calibration(calibration, settings.adjustment);
  const auto yaml = calibration_yaml(settings.adjustment, calibration.scans);
  if (options.json) {
    std::cout << nlohmann::json{{"files", files},
                                {"status", bad_file ? "partial" : "ok"},
                                {"scans", calibration.scans},
                                {"rejected", calibration.rejected},
                                {"scatter", calibration.scatter},
                                {"range_bias_m", calibration.range_bias},
                                {"range_bias_sigma_m", calibration.range_bias_sigma},
                                {"range_bias_servo_sigma_m", calibration.servo_sigmas[0]},
                                {"lever_arm_m", calibration.lever_arm},
                                {"lever_arm_sigma_m", calibration.lever_arm_sigma},
                                {"lever_arm_servo_sigma_m", calibration.servo_sigmas[1]},
                                {"pitch_offset_rad", calibration.pitch_offset},
                                {"pitch_offset_sigma_rad", calibration.pitch_offset_sigma},
                                {"pitch_offset_servo_sigma_rad", calibration.servo_sigmas[2]},
                                {"config", yaml}}
              << "\n";
  } else {
    std::printf(
        "\nthe unit's own terms from %zu scans (%zu left out, far from the others): range bias %+.2f mm (+-%.2f), "
        "lever arm %+.2f mm (+-%.2f), servo offset %+.3f deg (+-%.3f); the scans disagree %.1f times over their "
        "information. The sigmas carry the servo's own error at each step (the same in every scan) at the steps' "
        "%.1f deg prior (none at 0); the config's priors are at least %.0f mm, %.0f mm and %.1f deg "
        "(docs/room_evaluation.md). "
        "For its config:\n\n%s",
        calibration.scans, calibration.rejected, 1e3 * calibration.range_bias, 1e3 * calibration.range_bias_sigma,
        1e3 * calibration.lever_arm, 1e3 * calibration.lever_arm_sigma, calibration.pitch_offset * 180 / M_PI,
        calibration.pitch_offset_sigma * 180 / M_PI, calibration.scatter, settings.adjustment.step_error_prior_deg,
        1e3 * room_measurement::kMinimumPriors.range_bias, 1e3 * room_measurement::kMinimumPriors.lever_arm,
        room_measurement::kMinimumPriors.pitch_offset_deg, yaml.c_str());
  }
  return bad_file ? 2 : 0;
}

}  // namespace

void add_room_command(CLI::App& app, int& exit_code) {
  static RoomOptions options;
  auto* room = app.add_subcommand("room", "Rooms: measure walls, corners and floor area from a scanned cloud");
  room->require_subcommand(1);
  auto* measure = room->add_subcommand("measure", "Measure a room from a PCD, PLY or XYZ file (scanner at the origin)");
  measure->add_option("file", options.file, "Cloud file: .pcd, .ply, .xyz")->required();
  measure->add_option("--unit", options.unit, "Unit of the file's coordinates")
      ->check(CLI::IsMember({"m", "cm", "mm"}));
  measure->add_option("--config", options.config, "YAML with a room_measurement section (defaults: the thesis's)");
  measure->add_flag("--json", options.json, "Print one JSON object");
  measure->add_option("--plan", options.plan, "Draw the floor plan to this .png, .svg or .dxf (CAD, metres)");
  on_run(*measure, exit_code, [] { return run_measure(options); });

  static CalibrateOptions calibrate_options;
  auto* calibrate = room->add_subcommand(
      "calibrate",
      "Calibrate a scanning unit's range bias, lever arm and servo offset from several of its room scans (different "
      "rooms or spots: walls seen from many angles); prints the config lines that apply it");
  calibrate->add_option("files", calibrate_options.files, "Cloud files of one unit's scans: .pcd, .ply, .xyz")
      ->required();
  calibrate->add_option("--unit", calibrate_options.unit, "Unit of the files' coordinates")
      ->check(CLI::IsMember({"m", "cm", "mm"}));
  calibrate->add_option("--config", calibrate_options.config,
                        "YAML with a room_measurement section (defaults: the thesis's)");
  calibrate->add_flag("--json", calibrate_options.json, "Print one JSON object");
  on_run(*calibrate, exit_code, [] { return run_calibrate(calibrate_options); });
}

}  // namespace scanbus::cli
