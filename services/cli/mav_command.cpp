// The MAV paper's scenarios: `scanbus sim mav` writes a flight with its truth as a MAV log;
// `scanbus eval mav` scores flights through the whole pipeline in one process (the paper's
// table, with the fusion beside it); `scanbus eval boxes` measures the boxes in any cloud.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "mav_messages.hpp"
#include "scanbus/cloud_io/cloud_files.hpp"
#include "scanbus/config.hpp"
#include "scanbus/ground_evaluation/flight_files.hpp"
#include "scanbus/mav_sim/flight.hpp"
#include "scanbus/pose_estimation/pose_estimator.hpp"

namespace scanbus::cli {

namespace {

using ground_evaluation::BoxEvaluation;
using ground_evaluation::FlightEvaluation;

constexpr const char* kRoman[] = {"", "I", "II", "III", "IV"};

struct FlightOptions {
  int scenario = 1;
  double duration = 180;
  double height = 3.0;
  std::vector<double> box{0.6, 0.4, 0.3};
  unsigned seed = 1;
  std::string gps = "rtk";
  double noise_scale = 1;  // every sensor error times this
  std::string pattern = "paper";
  double laser_rate = 30;  // Hz, the paper's laser
  int laser_rays = 361;    // at 0.25 degrees: the paper's 90 degrees; 1,081 spans 270 (a Hokuyo UTM-30LX)
  std::string terrain;     // a YAML file with a `terrain` map; empty: flat, as in the paper
};

mav_sim::FlightSettings flight_settings(const FlightOptions& options) {
  mav_sim::FlightSettings settings;
  settings.scenario = options.scenario;
  settings.duration = options.duration;
  settings.height = options.height;
  settings.box_size = {options.box[0], options.box[1], options.box[2]};
  settings.seed = options.seed;
  settings.laser.rate = options.laser_rate;
  settings.laser.field_of_view = (options.laser_rays - 1) * settings.laser.step;
  const mav_sim::GpsMode gps = options.gps == "float"        ? mav_sim::GpsMode::rtk_float
                               : options.gps == "standalone" ? mav_sim::GpsMode::standalone
                                                             : mav_sim::GpsMode::rtk_fixed;
  settings.noise = mav_sim::with_gps(settings.noise, gps);
  settings.noise_scale = options.noise_scale;
  settings.pattern = options.pattern == "lawnmower"    ? mav_sim::FlightPattern::lawnmower
                     : options.pattern == "climb"      ? mav_sim::FlightPattern::climb
                     : options.pattern == "hover-turn" ? mav_sim::FlightPattern::hover_turn
                                                       : mav_sim::FlightPattern::paper;
  if (!options.terrain.empty()) settings.terrain = mav_sim::load_terrain(options.terrain);
  return settings;
}

void add_flight_options(CLI::App& command, FlightOptions& options) {
  command.add_option("--duration", options.duration, "Seconds of flight")->check(CLI::Range(1.0, 3600.0));
  command.add_option("--height", options.height, "Mean height above the ground, m")->check(CLI::Range(0.5, 25.0));
  command.add_option("--box", options.box, "Scenario IV's boxes: length (along the flight), width, height in m")
      ->expected(3)
      ->delimiter(',');
  command.add_option("--seed", options.seed, "Noise seed");
  command
      .add_option("--gps", options.gps,
                  "GPS receiver's mode: rtk (fixed, centimetres), float (RTK float, "
                  "decimetres) or standalone (metres of wander)")
      ->check(CLI::IsMember({"rtk", "float", "standalone"}));
  command
      .add_option("--pattern", options.pattern,
                  "How the MAV flies over the scenario's ground: paper (the "
                  "scenario's own motion), lawnmower (four lanes 1.5 m apart), climb (passes climbing and "
                  "descending 1.5 m), hover-turn (turning on the spot)")
      ->check(CLI::IsMember({"paper", "lawnmower", "climb", "hover-turn"}));
  command
      .add_option("--noise-scale", options.noise_scale,
                  "Every simulated sensor error times this (0.5, 2: what "
                  "the fusion does when the real noise is half or twice what its defaults assume)")
      ->check(CLI::Range(0.0, 10.0));
  command.add_option("--laser-rate", options.laser_rate, "Laser scans per second")->check(CLI::Range(1.0, 200.0));
  command.add_option("--laser-rays", options.laser_rays, "Rays per scan, 0.25 degrees apart, centred on straight down")
      ->check(CLI::Range(2, 1441));
  command
      .add_option("--terrain", options.terrain,
                  "YAML file whose `terrain` map shapes the ground under the scenario "
                  "(slope, mounds, steps, roughness; config/terrain/slope_mound.yaml); default flat")
      ->check(CLI::ExistingFile);
}

struct SimOptions {
  FlightOptions flight;
  std::string out;
};

int run_sim_mav(const SimOptions& options) {
  const auto log = mav_sim::simulate_flight(flight_settings(options.flight));
  sensor_replay::save_mav_log(options.out, log);
  std::printf("wrote %s: scenario %s, %.0f s, %zu scans, %zu IMU, %zu GPS, %zu barometer, %zu truth samples\n",
              options.out.c_str(), kRoman[options.flight.scenario], options.flight.duration, log.lasers.size(),
              log.imus.size(), log.fixes.size(), log.baros.size(), log.truths.size());
  return 0;
}

nlohmann::json boxes_json(const BoxEvaluation& result) {
  nlohmann::json json{{"ok", result.ok}, {"ratio_actual", result.ratio_actual}};
  if (!result.ok) {
    json["message"] = result.message;
    return json;
  }
  json["performance_percent"] = result.mean_performance_percent;
  for (const auto& box : result.boxes) {
    json["boxes"].push_back({{"centre", {box.centre.x(), box.centre.y()}},
                             {"yaw_deg", box.yaw * 180 / M_PI},
                             {"length_m", box.length},
                             {"width_m", box.width},
                             {"height_m", box.height},
                             {"points", box.points},
                             {"error_percent", box.error_percent},
                             {"performance_percent", box.performance_percent}});
  }
  return json;
}

std::string performance_text(const BoxEvaluation& result) {
  if (!result.ok) return "-";
  char text[16];
  std::snprintf(text, sizeof text, "%.2f %%", result.mean_performance_percent);
  return text;
}

struct EvalMavOptions {
  std::vector<std::string> logs;
  std::vector<int> scenarios{1, 2, 3, 4};
  FlightOptions flight;
  std::string out;  // a folder for each flight's clouds (PCD), their top views (PNG) and the fused elevation GeoTIFF
  bool json = false;
  bool no_ground = false;
  bool first_solved = false;
  std::string config;           // a pose_estimation service config whose fusion settings to evaluate
  bool calibrate = false;       // the simulated unit's scan plane calibrated from its own hover-turn first
  std::string calibration_log;  // a hover-turn log of the same laser to calibrate the scan plane from
};

// The simulated unit's hover-turn: the same seed draws the same laser mount whatever the flight
// or the ground.
constexpr double kCalibrationFlight = 5 * 18 + 1;  // s: five whole turns (a turn takes 18 s)

nlohmann::json calibration_json(const pose_estimation::ScanPlaneCalibration& c) {
  nlohmann::json json{{"ok", c.ok}, {"status", c.status}};
  if (c.ok)
    json.update({{"rotation_deg", c.rotation * 180 / M_PI},
                 {"sigma_deg", c.sigma * 180 / M_PI},
                 {"scans", c.scans},
                 {"line_residual_m", c.line_residual}});
  return json;
}

// The calibration the options ask for, or none; throws MavLogError for an unreadable log.
std::optional<pose_estimation::ScanPlaneCalibration> scan_plane_calibration(const EvalMavOptions& options) {
  if (!options.calibration_log.empty())
    return ground_evaluation::calibrate_scan_plane(sensor_replay::load_mav_log(options.calibration_log));
  if (!options.calibrate) return std::nullopt;
  FlightOptions hover = options.flight;
  hover.scenario = 1;
  hover.pattern = "hover-turn";
  hover.duration = kCalibrationFlight;
  hover.terrain.clear();  // a level, even site (a car park), as calibrate_scan_plane asks
  return ground_evaluation::calibrate_scan_plane(mav_sim::simulate_flight(flight_settings(hover)));
}

nlohmann::json ground_error_json(const ground_evaluation::GroundModelError& g) {
  nlohmann::json json{{"rmse", g.rmse}, {"median", g.median}, {"p95", g.p95}, {"bias", g.bias}, {"points", g.points}};
  if (!std::isnan(g.slope_error))
    json.update({{"slope", {g.slope.x(), g.slope.y()}},
                 {"true_slope", {g.true_slope.x(), g.true_slope.y()}},
                 {"slope_error", g.slope_error}});
  return json;
}

nlohmann::json evaluation_json(const std::string& name, const FlightEvaluation& e) {
  nlohmann::json json{
      {"flight", name},
      {"scans", e.scans},
      {"poses", e.poses},
      {"failed_matches", e.matches_failed},
      {"rejected_changes", e.changes_rejected},
      {"clearances", e.clearances},
      {"ground_cells", e.ground_cells},
      {"fusion_ms_per_update", e.fusion_ms_per_update},
      {"fused_within_sigma", {{"1", e.fused_within_sigma[0]}, {"2", e.fused_within_sigma[1]}}},
      {"fused_immediate_within_sigma", {{"1", e.immediate_within_sigma[0]}, {"2", e.immediate_within_sigma[1]}}}};
  if (!e.has_ground) json["ground_error_note"] = "not measured: the log does not carry its true ground (META scenario)";
  const auto& grid = e.elevation;
  json["elevation_grid"] = {
      {"cell_m", grid.cell_size}, {"columns", grid.columns}, {"rows", grid.rows}, {"cells", grid.filled()}};
  if (e.has_ground && grid.filled() > 0) json["elevation_grid"]["error_m"] = ground_error_json(e.elevation_error);
  for (int source = 0; source < ground_evaluation::kHeightSources; ++source) {
    if (std::isnan(e.height_rmse[source])) continue;  // no such height in this log (GPS)
    json["height_rmse_m"][ground_evaluation::kHeightSourceNames[source]] = e.height_rmse[source];
    if (e.has_ground)
      json["ground_error_m"][ground_evaluation::kHeightSourceNames[source]] = ground_error_json(e.ground[source]);
    if (e.has_boxes) json["boxes"][ground_evaluation::kHeightSourceNames[source]] = boxes_json(e.boxes[source]);
  }
  json["height_rmse_m"]["fused_immediate"] = e.immediate_rmse;
  if (e.has_ground) json["ground_error_m"]["true_height"] = ground_error_json(e.ground_at_true_height);
  return json;
}

int run_eval_mav(EvalMavOptions options) {
  const bool progress = !options.json && isatty(STDOUT_FILENO);
  std::vector<std::pair<std::string, sensor_replay::MavLog>> flights;
  try {
    for (const auto& path : options.logs) flights.emplace_back(path, sensor_replay::load_mav_log(path));
  } catch (const sensor_replay::MavLogError& e) {
    std::cerr << "scanbus eval mav: " << e.what() << "\n";
    return 2;
  }
  if (options.logs.empty()) {
    for (int scenario : options.scenarios) {
      options.flight.scenario = scenario;
      if (progress) std::printf("\rsimulating scenario %s   ", kRoman[scenario]), std::fflush(stdout);
      flights.emplace_back(std::string("scenario ") + kRoman[scenario],
                           mav_sim::simulate_flight(flight_settings(options.flight)));
    }
  }
  ground_evaluation::FlightEvaluationSettings base;
  std::optional<pose_estimation::ScanPlaneCalibration> calibration;
  try {
    if (progress && (options.calibrate || !options.calibration_log.empty()))
      std::printf("\rcalibrating the laser's scan plane   "), std::fflush(stdout);
    calibration = scan_plane_calibration(options);
  } catch (const sensor_replay::MavLogError& e) {
    std::cerr << "scanbus eval mav: --calibration-log: " << e.what() << "\n";
    return 2;
  }
  if (calibration && !calibration->ok) {
    std::cerr << "scanbus eval mav: the scan plane is " << calibration->status << "\n";
    return 2;
  }
  if (calibration) base.scan_plane_rotation = calibration->rotation;
  try {
    if (!options.config.empty()) {
      const Config file = Config::load(options.config);
      const auto estimator = pose_estimation::pose_estimator_settings_from_config(file.section("pose_estimation"));
      base.fusion = estimator.fusion;
      base.ground_clearance = estimator.ground_clearance;
    }
  } catch (const std::exception& e) {
    std::cerr << "scanbus eval mav: config error: " << e.what() << "\n";
    return 2;
  }
  std::error_code made;  // before the flights' minutes, as `eval rooms --out` does
  if (!options.out.empty() && !std::filesystem::create_directories(options.out, made) && made) {
    std::cerr << "scanbus eval mav: --out " << options.out << ": " << made.message() << "\n";
    return 2;
  }
  std::vector<FlightEvaluation> evaluations;
  for (const auto& [name, log] : flights) {
    const std::string label = name;
    try {
      ground_evaluation::FlightEvaluationSettings settings = base;
      settings.ground_clearance = settings.ground_clearance && !options.no_ground;
      settings.settled_heights = !options.first_solved;
      settings.true_ground = mav_sim::scored_ground_of_log(log);
      evaluations.push_back(ground_evaluation::evaluate_flight(log, settings, [&](size_t done, size_t total) {
        if (progress)
          std::printf("\revaluating %s: %3.0f %%   ", label.c_str(), 100.0 * done / total), std::fflush(stdout);
      }));
    } catch (const sensor_replay::MavLogError& e) {
      if (progress) std::printf("\n");
      std::cerr << "scanbus eval mav: " << name << ": " << e.what() << "\n";
      return 2;
    }
    try {
      if (!options.out.empty()) ground_evaluation::write_flight_files(options.out, name, evaluations.back(), log);
    } catch (const std::runtime_error& e) {
      std::cerr << "scanbus eval mav: " << name << ": " << e.what() << "\n";
      return 2;
    }
  }
  if (progress) std::printf("\r%60s\r", "");
  if (calibration && !options.json)
    std::printf("laser scan plane calibrated: %s, applied to every flight\n", calibration->status.c_str());
  nlohmann::json results = nlohmann::json::array();
  if (!options.json)
    std::printf(
        "%-14s %6s %7s | height RMSE (m): %9s %12s %7s %6s %6s | boxes P: %9s %12s %8s | ground RMSE (m): %9s %12s "
        "%7s %6s %11s\n",
        "flight", "scans", "failed", "barometer", "scan matcher", "GPS", "fused", "ratio", "barometer", "scan matcher",
        "fused", "barometer", "scan matcher", "GPS", "fused", "true height");
  for (size_t i = 0; i < flights.size(); ++i) {
    const std::string& name = flights[i].first;
    const FlightEvaluation& evaluation = evaluations[i];
    if (options.json) {
      results.push_back(evaluation_json(name, evaluation));
      if (calibration) results.back()["scan_plane_calibration"] = calibration_json(*calibration);
      continue;
    }
    const double best = std::min(evaluation.height_rmse[0], evaluation.height_rmse[1]);
    std::printf("%-14s %6zu %7zu | %26.3f %12.3f %7.3f %6.3f %6.2f | %18s %12s %8s | ", name.c_str(), evaluation.scans,
                evaluation.matches_failed, evaluation.height_rmse[0], evaluation.height_rmse[1],
                evaluation.height_rmse[3], evaluation.height_rmse[2], evaluation.height_rmse[2] / best,
                performance_text(evaluation.boxes[0]).c_str(), performance_text(evaluation.boxes[1]).c_str(),
                performance_text(evaluation.boxes[2]).c_str());
    if (evaluation.has_ground)
      std::printf("%26.3f %12.3f %7.3f %6.3f %11.3f\n", evaluation.ground[0].rmse, evaluation.ground[1].rmse,
                  evaluation.ground[3].rmse, evaluation.ground[2].rmse, evaluation.ground_at_true_height.rmse);
    else
      std::printf("%66s\n", "not known (no META scenario)");
  }
  if (options.json) std::cout << results.dump() << "\n";
  return 0;
}

struct EvalBoxesOptions {
  std::string cloud;
  std::vector<double> truth;
  std::string unit = "m";
  bool json = false;
};

int run_eval_boxes(const EvalBoxesOptions& options) {
  std::vector<Eigen::Vector3f> cloud;
  try {
    cloud = cloud_io::read_cloud(options.cloud, cloud_io::metres_per_unit(options.unit));
  } catch (const cloud_io::CloudFileError& e) {
    std::cerr << "scanbus eval boxes: " << e.what() << "\n";
    return 2;
  }
  const BoxEvaluation result = ground_evaluation::evaluate_boxes(cloud, options.truth[0], options.truth[1]);
  if (options.json) {
    std::cout << boxes_json(result).dump() << "\n";
  } else if (!result.ok) {
    std::printf("no boxes measured: %s\n", result.message.c_str());
  } else {
    for (size_t i = 0; i < result.boxes.size(); ++i) {
      const auto& box = result.boxes[i];
      std::printf("box %zu at (%.3f, %.3f): %.4f x %.4f m, %.3f m high, %zu points: E %.2f %%, P %.2f %%\n", i + 1,
                  box.centre.x(), box.centre.y(), box.length, box.width, box.height, box.points, box.error_percent,
                  box.performance_percent);
    }
    std::printf("P = %.2f %% (true width/length %.4f)\n", result.mean_performance_percent, result.ratio_actual);
  }
  return result.ok ? 0 : 1;
}

struct EvalGroundOptions {
  std::string cloud, log, unit = "m";
  double cells = 0;  // > 0: the points are an elevation grid's cells of this size
  bool json = false;
};

// A map-frame ground cloud (from the services over DDS, or any tool) against the true ground
// of the simulated flight it was built from.
int run_eval_ground(const EvalGroundOptions& options) {
  try {
    auto truth = mav_sim::scored_ground_of_log(sensor_replay::load_mav_log(options.log));
    if (!truth) {
      std::cerr << "scanbus eval ground: " << options.log << ": not measured: the log does not carry its true ground "
                << "(META scenario: a simulated flight's)\n";
      return 2;
    }
    const auto cloud = cloud_io::read_cloud(options.cloud, cloud_io::metres_per_unit(options.unit));
    if (options.cells > 0) truth = ground_evaluation::cell_average_truth(truth, options.cells);
    const auto error = ground_evaluation::ground_model_error(cloud, truth);
    if (options.json) {
      std::cout << ground_error_json(error).dump() << "\n";
    } else {
      std::printf("%zu of %zu points scored: height error RMSE %.3f m, median %.3f m, p95 %.3f m, bias %+.3f m\n",
                  error.points, cloud.size(), error.rmse, error.median, error.p95, error.bias);
      if (!std::isnan(error.slope_error))
        std::printf("slope %.4f %.4f against the true %.4f %.4f: %.1f %% off\n", error.slope.x(), error.slope.y(),
                    error.true_slope.x(), error.true_slope.y(), 100 * error.slope_error);
    }
    return error.points > 0 ? 0 : 1;
  } catch (const sensor_replay::MavLogError& e) {
    std::cerr << "scanbus eval ground: " << e.what() << "\n";
  } catch (const cloud_io::CloudFileError& e) {
    std::cerr << "scanbus eval ground: " << e.what() << "\n";
  }
  return 2;
}

}  // namespace

void add_mav_sim_command(CLI::App& sim, int& exit_code) {
  static SimOptions options;
  auto* command =
      sim.add_subcommand("mav", "A MAV flight of the paper's scenarios I-IV with ground truth, as a MAV log");
  command
      ->add_option("--scenario", options.flight.scenario,
                   "1 forward flight, 2 rotational hover in wind, "
                   "3 corner-like ground, 4 two boxes")
      ->check(CLI::Range(1, 4));
  add_flight_options(*command, options.flight);
  command
      ->add_option(
          "--out", options.out,
          "The MAV log to write: text (docs/mav_log.md), or an MCAP recording of its topics when it ends in .mcap")
      ->required();
  on_run(*command, exit_code, [] { return run_sim_mav(options); });
}

void add_eval_command(CLI::App& app, int& exit_code) {
  auto* eval =
      app.add_subcommand("eval", "Evaluations against truth: MAV flights, boxes in a ground cloud, simulated rooms");
  eval->require_subcommand(1);
  add_eval_rooms_command(*eval, exit_code);

  static EvalMavOptions mav;
  auto* flights = eval->add_subcommand("mav",
                                       "Height RMSE and box P of MAV flights through the whole pipeline "
                                       "(simulated scenarios unless --log is given)");
  auto* logs = flights->add_option("--log", mav.logs, "MAV logs to evaluate (text or .mcap)")->check(CLI::ExistingFile);
  flights->add_option("--scenarios", mav.scenarios, "Scenarios to simulate and evaluate")
      ->delimiter(',')
      ->check(CLI::Range(1, 4));
  add_flight_options(*flights, mav.flight);
  flights->add_option(
      "--out", mav.out,
      "Folder (made if missing) for each flight's clouds (PCD), height-coloured top views (PNG), heights (CSV) "
      "and the fused cloud's elevation grid (GeoTIFF)");
  flights->add_flag("--json", mav.json, "One JSON array, no progress");
  flights
      ->add_option("--config", mav.config,
                   "A pose_estimation service config (config/services/pose_estimation.yaml) "
                   "whose fusion settings to evaluate; default: the shipped defaults")
      ->check(CLI::ExistingFile);
  flights->add_flag(
      "--no-ground", mav.no_ground,
      "Fuse the barometer, GPS altitude and the scan matcher's changes only, without the ground the scans see");
  flights->add_flag("--first-solved", mav.first_solved,
                    "Place the scans by the fused heights as first solved (rt/pose), not as they left the fusion's "
                    "window (rt/pose/settled, what cloud_assembly uses): the two side by side");
  flights
      ->add_flag("--calibrate", mav.calibrate,
                 "Calibrate the simulated laser's rotation in its scan plane from the same unit's "
                 "hover-turn (five turns) first, and place every flight's scans with it")
      ->excludes(logs);
  flights
      ->add_option("--calibration-log", mav.calibration_log,
                   "A hover-turn MAV log of the same laser to calibrate its scan plane from (scanbus calibrate "
                   "scan-plane), applied to every flight")
      ->check(CLI::ExistingFile)
      ->excludes("--calibrate");
  on_run(*flights, exit_code, [] { return run_eval_mav(mav); });

  static EvalBoxesOptions boxes;
  auto* measure = eval->add_subcommand("boxes",
                                       "Find the two boxes in a ground cloud and score their width/length "
                                       "ratio (the MAV paper's E and P)");
  measure->add_option("cloud", boxes.cloud, "PCD, PLY or XYZ cloud")->required()->check(CLI::ExistingFile);
  measure->add_option("--truth", boxes.truth, "True width,length of the boxes (m)")
      ->required()
      ->expected(2)
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  measure->add_option("--unit", boxes.unit, "Unit of the cloud's coordinates")->check(CLI::IsMember({"m", "cm", "mm"}));
  measure->add_flag("--json", boxes.json, "One JSON object");
  on_run(*measure, exit_code, [] { return run_eval_boxes(boxes); });

  static EvalGroundOptions ground;
  auto* scoring = eval->add_subcommand("ground",
                                       "Score a map-frame ground cloud against the true ground of the simulated "
                                       "MAV flight it was built from (height error, tilt)");
  scoring->add_option("cloud", ground.cloud, "PCD, PLY or XYZ cloud in the map frame")
      ->required()
      ->check(CLI::ExistingFile);
  scoring->add_option("--log", ground.log, "The simulated MAV log (text or .mcap) whose META describes the ground")
      ->required()
      ->check(CLI::ExistingFile);
  scoring->add_option("--unit", ground.unit, "Unit of the cloud's coordinates")
      ->check(CLI::IsMember({"m", "cm", "mm"}));
  scoring
      ->add_option("--cells", ground.cells,
                   "The points are an elevation grid's cells this wide (m, rt/cloud/elevation): "
                   "each against the true ground averaged over its cell; cells an edge crosses are not scored")
      ->check(CLI::PositiveNumber);
  scoring->add_flag("--json", ground.json, "One JSON object");
  on_run(*scoring, exit_code, [] { return run_eval_ground(ground); });
}

void add_calibrate_command(CLI::App& app, int& exit_code) {
  static std::string log;
  static bool json = false;
  auto* calibrate = app.add_subcommand("calibrate", "Sensor calibration from recorded flights");
  calibrate->require_subcommand(1);
  auto* plane = calibrate->add_subcommand(
      "scan-plane",
      "The MAV laser's rotation in its scan plane from a hover-turn log (three whole turns or more): "
      "pose_estimation's laser_mount.scan_plane_rotation");
  plane->add_option("--log", log, "The hover-turn MAV log (text or .mcap)")->required()->check(CLI::ExistingFile);
  plane->add_flag("--json", json, "One JSON object");
  on_run(*plane, exit_code, [] {
    pose_estimation::ScanPlaneCalibration calibration;
    try {
      calibration = ground_evaluation::calibrate_scan_plane(sensor_replay::load_mav_log(log));
    } catch (const sensor_replay::MavLogError& e) {
      std::cerr << "scanbus calibrate scan-plane: " << e.what() << "\n";
      return 2;
    }
    if (json) {
      std::cout << calibration_json(calibration).dump() << "\n";
    } else if (calibration.ok) {
      std::printf("%s\npose_estimation:\n  laser_mount:\n    scan_plane_rotation: %.3f  # degrees, +- %.3f\n",
                  calibration.status.c_str(), calibration.rotation * 180 / M_PI, calibration.sigma * 180 / M_PI);
    } else {
      std::cerr << "scanbus calibrate scan-plane: " << calibration.status << "\n";
    }
    return calibration.ok ? 0 : 1;
  });
}

}  // namespace scanbus::cli
