#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "commands.hpp"
#include "scanbus/scan_matcher/laser_log.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"

namespace scanbus::cli {

namespace {

using namespace scan_matcher;

struct EvalOptions {
  std::string log, relations, config, trajectory;
  bool odometry_guess = false;
  bool json = false;
  double max_span = 10.0;  // s, for the separate short-relation figures
};

nlohmann::json stats_json(const ErrorStats& stats, double scale) {
  return {{"mean", stats.mean * scale}, {"std", stats.std * scale}, {"max", stats.max * scale}};
}

// The `scan_matcher.matcher` section of a scan_matcher service file; defaults without one.
MatcherSettings load_matcher_settings(const std::string& path) {
  if (path.empty()) return {};
  const Config section = Config::load(path).section("scan_matcher").section("matcher");
  MatcherSettings settings = matcher_settings_from_config(section);
  section.check_all_read();
  return settings;
}

// One line per scan, "stamp x y theta", as TUM-style trajectory tools read them.
void write_trajectory(const std::string& path, const std::vector<double>& stamps, const std::vector<Pose2>& poses) {
  std::ofstream out(path);
  out << std::fixed;
  out.precision(6);
  for (size_t i = 0; i < poses.size(); ++i)
    out << stamps[i] << ' ' << poses[i].x << ' ' << poses[i].y << ' ' << poses[i].theta << '\n';
  if (!out) throw std::runtime_error(path + ": cannot write the trajectory");
}

int run_eval(const EvalOptions& options) {
  std::vector<LaserRecord> records;
  std::vector<Relation> relations;
  MatcherSettings settings;
  try {
    settings = load_matcher_settings(options.config);
    records = read_carmen_log(options.log);
    relations = read_relations(options.relations);
  } catch (const std::runtime_error& e) {  // LogError, ConfigError
    std::cerr << "scanbus scanmatch eval: " << e.what() << "\n";
    return 2;
  }
  const bool progress = !options.json && isatty(STDOUT_FILENO);
  ScanMatcher matcher(settings);
  std::vector<double> stamps;
  std::vector<Pose2> poses;
  size_t failed = 0;
  double matching_seconds = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    const LaserRecord& record = records[i];
    std::optional<Pose2> guess;
    if (options.odometry_guess && i > 0) guess = records[i - 1].odometry.inverse() * record.odometry;
    const auto started = std::chrono::steady_clock::now();
    const MatchResult result = matcher.add_scan({record.angle_min, record.angle_increment, record.ranges}, guess);
    matching_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    failed += i > 0 && result.quality != MatchQuality::Ok;
    stamps.push_back(record.stamp);
    poses.push_back(result.pose);
    if (progress && (i % 50 == 0 || i + 1 == records.size()))
      std::printf("\rmatching: scan %zu of %zu", i + 1, records.size()), std::fflush(stdout);
  }
  if (progress) std::printf("\n");
  if (!options.trajectory.empty()) write_trajectory(options.trajectory, stamps, poses);
  const RelationErrors all = evaluate_relations(stamps, poses, relations);
  const RelationErrors short_span = evaluate_relations(stamps, poses, relations, options.max_span);
  const double rate = static_cast<double>(records.size()) / std::max(matching_seconds, 1e-9);
  if (options.json) {
    std::cout << nlohmann::json{{"translational_error_m", stats_json(all.translational, 1)},
                                {"rotational_error_deg", stats_json(all.rotational, 180 / M_PI)},
                                {"relations", all.translational.count},
                                {"relations_missing", all.missing},
                                {"short_relations", {{"max_span_s", options.max_span},
                                                     {"relations", short_span.translational.count},
                                                     {"translational_error_m", stats_json(short_span.translational, 1)},
                                                     {"rotational_error_deg", stats_json(short_span.rotational, 180 / M_PI)}}},
                                {"scans", records.size()},
                                {"failed_matches", failed},
                                {"odometry_guess", options.odometry_guess},
                                {"scans_per_second", rate}}
              << "\n";
    return 0;
  }
  auto line = [](const char* name, const RelationErrors& e) {
    std::printf("%s: %zu relations, translational %.3f +- %.3f m (max %.3f), rotational %.2f +- %.2f deg (max %.2f)\n",
                name, e.translational.count, e.translational.mean, e.translational.std, e.translational.max,
                e.rotational.mean * 180 / M_PI, e.rotational.std * 180 / M_PI, e.rotational.max * 180 / M_PI);
  };
  line("all relations", all);
  char name[64];
  std::snprintf(name, sizeof(name), "relations within %.0f s", options.max_span);
  line(name, short_span);
  std::printf("%zu scans, %zu failed matches, %.0f scans per second%s\n", records.size(), failed, rate,
              options.odometry_guess ? ", odometry as initial guess" : "");
  return 0;
}

}  // namespace

void add_scanmatch_command(CLI::App& app, int& exit_code) {
  static EvalOptions options;
  auto* scanmatch = app.add_subcommand("scanmatch", "Laser scan matching (PL-ICP)");
  scanmatch->require_subcommand(1);
  auto* eval = scanmatch->add_subcommand("eval", "Match a CARMEN log's scans and score them against relations");
  eval->add_option("--log", options.log, "CARMEN log (FLASER or ROBOTLASER1 lines)")->required();
  eval->add_option("--relations", options.relations, "Relations file (t1 t2 x y z roll pitch yaw)")->required();
  eval->add_option("--config", options.config, "Service file with a scan_matcher.matcher section (default: built-in)");
  eval->add_option("--trajectory", options.trajectory, "Write the matched poses, one 'stamp x y theta' line per scan");
  eval->add_flag("--odometry-guess", options.odometry_guess, "Use wheel odometry as each match's initial guess");
  eval->add_option("--max-span", options.max_span, "Also report relations at most this many seconds apart");
  eval->add_flag("--json", options.json, "Print one JSON object");
  on_run(*eval, exit_code, [] { return run_eval(options); });
}

}  // namespace scanbus::cli
