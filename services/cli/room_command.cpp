#include <iostream>

#include "commands.hpp"
#include "room_measurement_node.hpp"
#include "room_report.hpp"
#include "scanbus/cloud_io/cloud_files.hpp"
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
  room_measurement::RoomSettings settings;
  try {
    if (!options.config.empty()) settings = room_measurement::room_settings_from_file(options.config);
  } catch (const ConfigError& e) {
    std::cerr << "scanbus room measure: config error: " << e.what() << "\n";
    return 2;
  }
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
}

}  // namespace scanbus::cli
