// `scanbus eval rooms`: the room measurement on a seeded sweep of simulated rooms.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>

#include "commands.hpp"
#include "room_measurement_node.hpp"
#include "room_report.hpp"
#include "scanbus/cloud_io/cloud_files.hpp"
#include "scanbus/room_evaluation/room_evaluation.hpp"
#include "scanbus/room_plan/floor_plan.hpp"
#include "scanbus/sim/room_file.hpp"
#include "scanbus/units.hpp"

namespace scanbus::cli {

namespace {

struct EvalRoomsOptions {
  room_evaluation::SweepOptions sweep;
  std::optional<unsigned> calibrate_on;  // first seed of the unit's calibration sweep
  std::string config;
  bool json = false;
  bool cases = false;
  std::string out;
};

// Each room's scan (PCD), measured floor plan (PNG and DXF) and true room (a room file for
// `scanbus sim scanner --room`), named by category and seed.
void write_cases(const std::string& folder, const std::vector<room_evaluation::RoomCase>& cases) {
  for (const auto& c : cases) {
    const std::string name = folder + "/" + sim::category_name(c.category) + "_" + std::to_string(c.seed);
    std::vector<CloudPoint> points;
    for (const auto& p : c.cloud) points.push_back({p, 0});
    cloud_io::write_pcd(name + ".pcd", points);
    room_plan::write_floor_plan(name + "_plan.png", c.measurement, name, c.cloud);
    room_plan::write_floor_plan(name + "_plan.dxf", c.measurement, name);
    std::ofstream room(name + "_room.yaml");
    room << sim::room_to_yaml(c.room);
    if (!room.flush()) throw std::runtime_error("cannot write " + name + "_room.yaml");
  }
}

nlohmann::json summary_json(const room_evaluation::SweepSummary& s) {
  nlohmann::json out = {{"category", s.category},
                        {"rooms", s.rooms},
                        {"measurable", s.measurable},
                        {"measured", s.measured},
                        {"inferred", s.inferred},
                        {"within_target", s.within_target},
                        {"wrong", s.wrong},
                        {"ok_over_2cm", s.ok_over_2cm},
                        {"refused", s.refused},
                        {"refused_wrongly", s.refused_wrongly},
                        {"walls", s.walls},
                        {"median_wall_error_m", s.median_wall_error},
                        {"p95_wall_error_m", s.p95_wall_error},
                        {"max_wall_error_m", s.max_wall_error},
                        {"p95_area_error", s.p95_area_error},
                        {"max_area_error", s.max_area_error},
                        {"walls_within_1_sigma", s.within_1_sigma},
                        {"walls_within_2_sigma", s.within_2_sigma},
                        {"corners", s.corners},
                        {"median_corner_error_m", s.median_corner_error},
                        {"max_corner_error_m", s.max_corner_error},
                        {"corners_within_1_sigma", s.corners_within_1_sigma},
                        {"corners_within_2_sigma", s.corners_within_2_sigma},
                        {"true_openings", s.true_openings},
                        {"openings_found", s.openings_found},
                        {"spurious_openings", s.spurious_openings},
                        {"median_opening_error_m", s.median_opening_error},
                        {"max_opening_error_m", s.max_opening_error},
                        {"worst_ceiling_error_m", nullptr}};
  if (s.worst_ceiling_error) out["worst_ceiling_error_m"] = *s.worst_ceiling_error;
  return out;
}

nlohmann::json case_json(const room_evaluation::RoomCase& c) {
  nlohmann::json walls = nlohmann::json::array();
  for (const auto& w : c.walls)
    walls.push_back({{"true_m", w.true_length}, {"measured_m", w.length}, {"sigma_m", w.sigma}});
  nlohmann::json openings = nlohmann::json::array();
  for (const auto& o : c.openings)
    openings.push_back({{"true_m", {o.true_from, o.true_to}}, {"found", o.found}, {"measured_m", {o.from, o.to}}});
  nlohmann::json out = {{"category", sim::category_name(c.category)},
                        {"seed", c.seed},
                        {"true_walls", c.true_walls},
                        {"measurable", c.measurable},
                        {"unseen", c.unseen},
                        {"status", room_measurement::status_name(c.status)},
                        {"message", c.message},
                        {"verdict", room_evaluation::verdict_name(c.verdict)},
                        {"walls", walls},
                        {"openings", openings},
                        {"spurious_openings", c.spurious_openings},
                        {"true_area_m2", c.true_area},
                        {"area_m2", c.area},
                        {"area_sigma_m2", c.area_sigma},
                        {"true_ceiling_height_m", c.true_ceiling_height.value_or(NAN)},
                        {"ceiling_height_m", nullptr},
                        {"points", c.points},
                        {"elapsed_ms", c.elapsed_ms}};
  if (c.ceiling_height) out["ceiling_height_m"] = *c.ceiling_height;
  return out;
}

void print_table(const std::vector<room_evaluation::SweepSummary>& summaries) {
  std::printf("%-15s %5s %5s %5s %6s %5s %5s %5s %7s %9s %9s %9s %8s %6s %6s\n", "category", "rooms", "seen", "ok",
              "target", "infer", "wrong", ">2cm", "refused", "median_m", "p95_m", "max_m", "area_max", "1sig", "2sig");
  for (const auto& s : summaries)
    std::printf("%-15s %5zu %5zu %5zu %6zu %5zu %5zu %5zu %3zu/%-3zu %9.4f %9.4f %9.4f %7.2f%% %5.0f%% %5.0f%%\n",
                s.category.c_str(), s.rooms, s.measurable, s.measured, s.within_target, s.inferred, s.wrong,
                s.ok_over_2cm, s.refused, s.refused_wrongly, s.median_wall_error, s.p95_wall_error, s.max_wall_error,
                100 * s.max_area_error, 100 * s.within_1_sigma, 100 * s.within_2_sigma);
  std::printf(
      "seen: every wall in view; ok: measured with the right walls, all seen; target: every wall within 1 cm and the "
      "area within 0.5 %%;\ninfer: right walls, some not seen but inferred (errors and sigmas counted); >2cm: ok with "
      "a wall more than 2 cm off or wrong walls; refused: right/wrongly "
      "(a room in view); errors over matched walls; 1sig/2sig: walls within 1 and 2 sigma\n");
  std::printf("\n%-15s %7s %10s %9s %6s %6s\n", "corners", "corners", "median_m", "max_m", "1sig", "2sig");
  for (const auto& s : summaries)
    if (s.corners > 0)
      std::printf("%-15s %7zu %10.4f %9.4f %5.0f%% %5.0f%%\n", s.category.c_str(), s.corners, s.median_corner_error,
                  s.max_corner_error, 100 * s.corners_within_1_sigma, 100 * s.corners_within_2_sigma);
  std::printf(
      "distance of each corner of a measured or inferred room from the true one; 1sig/2sig: within 1 and 2 of its "
      "sigmas\n");
  std::printf("\n%-15s %11s %9s %15s %12s\n", "openings", "found/true", "spurious", "median_edge_m", "max_edge_m");
  for (const auto& s : summaries)
    if (s.true_openings + s.spurious_openings > 0)
      std::printf("%-15s %5zu/%-5zu %9zu %15.3f %12.3f\n", s.category.c_str(), s.openings_found, s.true_openings,
                  s.spurious_openings, s.median_opening_error, s.max_opening_error);
  std::printf(
      "on the walls of rooms measured or inferred; found: a measured opening covers at least half of the true one; "
      "edge: the farther of its two ends from the true one's\n");
}

nlohmann::json calibration_json(const room_evaluation::SweepCalibration& s) {
  const auto& c = s.calibration;
  return {{"scans", c.scans},
          {"rejected", c.rejected},
          {"scatter", c.scatter},
          {"range_bias_m",
           {{"estimate", c.range_bias},
            {"sigma", c.range_bias_sigma},
            {"servo_sigma", c.servo_sigmas[0]},
            {"truth", s.true_range_bias}}},
          {"lever_arm_m",
           {{"estimate", c.lever_arm},
            {"sigma", c.lever_arm_sigma},
            {"servo_sigma", c.servo_sigmas[1]},
            {"truth", s.true_lever_arm}}},
          {"pitch_offset_rad",
           {{"estimate", c.pitch_offset},
            {"sigma", c.pitch_offset_sigma},
            {"servo_sigma", c.servo_sigmas[2]},
            {"truth", s.true_pitch_offset}}}};
}

nlohmann::json unit_json(const sim::HardwareSettings& unit) {
  const auto& e = unit.errors;
  return {{"range_noise_m", unit.range_noise},   {"range_noise_per_m", e.range_noise_per_m},
          {"range_bias_added_m", e.range_bias},  {"lever_arm_m", e.lever_arm},
          {"servo_offset_rad", e.servo_offset},  {"servo_step_error_rad", e.servo_error},
          {"yaw_runout_rad", e.yaw_eccentricity}};
}

void print_unit(const sim::HardwareSettings& unit, unsigned unit_seed) {
  const auto& e = unit.errors;
  std::printf(
      "unit %u (simulated): range noise %.2f cm + %.2f cm per m, range bias %+.1f mm (added to every range), "
      "lever arm %.1f mm, servo offset %+.3f deg, each step %.2f deg (one sigma), gear runout %.3f deg\n",
      unit_seed, 100 * unit.range_noise, 100 * e.range_noise_per_m, 1e3 * e.range_bias, 1e3 * e.lever_arm,
      e.servo_offset / kDegree, e.servo_error / kDegree, e.yaw_eccentricity / kDegree);
}

void print_calibration(const room_evaluation::SweepCalibration& s, unsigned first_seed) {
  const auto& c = s.calibration;
  std::printf(
      "unit calibrated on %zu of its scans (%zu left out; seeds %u on): range bias %+.1f mm (+-%.1f; the unit's own "
      "%+.1f), lever arm %+.1f mm (+-%.1f; %+.1f), servo offset %+.3f deg (+-%.3f; %+.3f); the scans disagree %.1f "
      "times over their information\n\n",
      c.scans, c.rejected, first_seed, 1e3 * c.range_bias, 1e3 * c.range_bias_sigma, 1e3 * s.true_range_bias,
      1e3 * c.lever_arm, 1e3 * c.lever_arm_sigma, 1e3 * s.true_lever_arm, c.pitch_offset / kDegree,
      c.pitch_offset_sigma / kDegree, s.true_pitch_offset / kDegree, c.scatter);
}

int run_eval_rooms(const EvalRoomsOptions& options) {
  auto loaded = room_settings_for(options.config, "eval rooms");
  if (!loaded) return 2;
  room_measurement::RoomSettings& settings = *loaded;
  const bool progress = !options.json && isatty(STDOUT_FILENO);
  if (!options.out.empty()) std::filesystem::create_directories(options.out);  // before the sweep's seconds
  auto sweep = [&](const room_evaluation::SweepOptions& sweep_options, const char* what) {
    auto cases = room_evaluation::evaluate_sweep(sweep_options, settings, [&](size_t done, size_t total) {
      if (progress) std::printf("\r%s room %zu of %zu   ", what, done, total), std::fflush(stdout);
    });
    if (progress) std::printf("\r%60s\r", "");
    return cases;
  };
  std::optional<room_evaluation::SweepCalibration> calibration;
  if (options.calibrate_on) {
    const int categories = static_cast<int>(options.sweep.categories.size());
    const int per_category = std::max(1, (options.sweep.count + categories - 1) / categories);  // as evaluate_sweep
    const long apart = static_cast<long>(*options.calibrate_on) - static_cast<long>(options.sweep.first_seed);
    if (std::abs(apart) < per_category)  // the same rooms would calibrate and be scored
      std::cerr << "scanbus eval rooms: warning: --calibrate-on " << *options.calibrate_on
                << " overlaps the scored seeds from " << options.sweep.first_seed << "\n";
    room_evaluation::SweepOptions calibration_sweep = options.sweep;
    calibration_sweep.first_seed = *options.calibrate_on;
    calibration_sweep.keep_clouds = false;
    try {
      calibration = room_evaluation::calibrate_on(sweep(calibration_sweep, "calibrating on"), options.sweep.unit_seed);
    } catch (const std::invalid_argument& e) {
      std::cerr << "scanbus eval rooms: " << e.what() << "\n";
      return 1;
    }
    room_measurement::apply_calibration(calibration->calibration, settings.adjustment);
  }
  const auto cases = sweep(options.sweep, "scanning and measuring");
  if (!options.out.empty()) write_cases(options.out, cases);
  const auto summaries = room_evaluation::summarize(cases);
  if (options.json) {
    nlohmann::json out = {{"summary", nlohmann::json::array()}, {"rooms", nlohmann::json::array()}};
    for (const auto& s : summaries) out["summary"].push_back(summary_json(s));
    for (const auto& c : cases) out["rooms"].push_back(case_json(c));
    if (calibration) out["calibration"] = calibration_json(*calibration);
    if (options.sweep.unit_seed != 0) out["unit"] = unit_json(room_evaluation::unit_of(options.sweep.unit_seed));
    std::cout << out.dump() << "\n";
    return 0;
  }
  if (options.sweep.unit_seed != 0)
    print_unit(room_evaluation::unit_of(options.sweep.unit_seed), options.sweep.unit_seed);
  if (calibration) print_calibration(*calibration, *options.calibrate_on);
  if (options.cases)
    for (const auto& c : cases) {
      std::printf("%-15s seed %3u: %-15s %-18s walls %zu, max error %.4f m, area %.3f (true %.3f) m2%s%s: %s\n",
                  sim::category_name(c.category), c.seed, room_evaluation::verdict_name(c.verdict),
                  room_measurement::status_name(c.status), c.true_walls, c.max_wall_error(), c.area, c.true_area,
                  c.measurable ? "" : ", not seen: ", c.unseen.c_str(), c.message.c_str());
    }
  print_table(summaries);
  return 0;
}

std::string category_names() {
  std::string names;
  for (auto category : sim::room_categories())
    names += (names.empty() ? "" : ", ") + std::string(sim::category_name(category));
  return names;
}

}  // namespace

void add_eval_rooms_command(CLI::App& eval, int& exit_code) {
  static EvalRoomsOptions options;
  auto* rooms = eval.add_subcommand("rooms",
                                    "Room measurement on a seeded sweep of simulated rooms (doors, windows, "
                                    "alcoves, L and T shapes, angled walls, furniture, closets, built-in units), "
                                    "scanned through the firmware simulator with a device's imperfections; no DDS");
  rooms->add_option("--count", options.sweep.count, "Rooms, spread over the categories swept (seeds from --seed on)")
      ->check(CLI::Range(1, 100000));
  rooms->add_option("--seed", options.sweep.first_seed, "First seed of each category");
  rooms
      ->add_option_function<std::vector<std::string>>(
          "--category",
          [](const std::vector<std::string>& names) {
            options.sweep.categories.clear();
            for (const auto& name : names) {
              const auto category = sim::category_named(name);
              auto& chosen = options.sweep.categories;
              if (std::find(chosen.begin(), chosen.end(), category) == chosen.end()) chosen.push_back(category);
            }
          },
          "Only these categories (" + category_names() + ")")
      ->check([](const std::string& name) {
        try {
          sim::category_named(name);
          return std::string();
        } catch (const std::invalid_argument& e) {
          return std::string(e.what());
        }
      });
  rooms->add_option("--threads", options.sweep.threads, "Worker threads (0: one per core)")->check(CLI::Range(0, 256));
  auto* ideal = rooms->add_flag("--ideal-device", options.sweep.ideal_device,
                                "Scan with the ideal device of the thesis's equations (2 cm noise, no imperfections)");
  auto* unit = rooms->add_option("--unit-seed", options.sweep.unit_seed,
                                 "Scan every room with one unit (its errors drawn from this seed, not 0), as a "
                                 "user's own device; default: a new device per room");
  unit->check(CLI::Range(1u, std::numeric_limits<unsigned>::max()))->excludes(ideal);
  rooms
      ->add_option("--calibrate-on", options.calibrate_on,
                   "Calibrate the unit first on the same sweep from this seed on (other rooms than those scored), "
                   "and measure with its calibration")
      ->needs(unit);
  rooms
      ->add_option("--out", options.out,
                   "Folder (made if missing) for each room's scan (PCD), floor plan (PNG, DXF) and true room (YAML)")
      ->each([](const std::string&) { options.sweep.keep_clouds = true; });
  rooms
      ->add_option("--config", options.config,
                   "YAML with a room_measurement section to evaluate (defaults: the shipped ones)")
      ->check(CLI::ExistingFile);
  rooms->add_flag("--cases", options.cases, "Also print a line for every room");
  rooms->add_flag("--json", options.json, "One JSON object (summary and every room), no progress");
  on_run(*rooms, exit_code, [] { return run_eval_rooms(options); });
}

}  // namespace scanbus::cli
