#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "scanbus/scan_matcher/laser_log.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"

namespace scanbus::cli {

namespace {

using namespace scan_matcher;

struct EvalOptions {
  std::string log, relations;
  bool odometry_guess = false;
  bool json = false;
  double max_span = 10.0;  // s, for the separate short-relation figures
};

nlohmann::json stats_json(const ErrorStats& stats, double scale) {
  return {{"mean", stats.mean * scale}, {"std", stats.std * scale}, {"max", stats.max * scale}};
}

int run_eval(const EvalOptions& options) {
  std::vector<LaserRecord> records;
  std::vector<Relation> relations;
  try {
    records = read_carmen_log(options.log);
    relations = read_relations(options.relations);
  } catch (const LogError& e) {
    std::cerr << "scanbus scanmatch eval: " << e.what() << "\n";
    return 2;
  }
  const bool progress = !options.json && isatty(STDOUT_FILENO);
  ScanMatcher matcher;
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
  eval->add_flag("--odometry-guess", options.odometry_guess, "Use wheel odometry as each match's initial guess");
  eval->add_option("--max-span", options.max_span, "Also report relations at most this many seconds apart");
  eval->add_flag("--json", options.json, "Print one JSON object");
  on_run(*eval, exit_code, [] { return run_eval(options); });
}

}  // namespace scanbus::cli
