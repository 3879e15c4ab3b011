#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "commands.hpp"
#include "laser_mcap.hpp"
#include "scanbus/plot/backtransform_picture.hpp"
#include "scanbus/scan_matcher/backtransform.hpp"
#include "scanbus/scan_matcher/laser_log.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"
#include "scanbus/scan_matcher/trajectory.hpp"

namespace scanbus::cli {

namespace {

using namespace scan_matcher;

struct EvalOptions {
  std::vector<std::string> logs, relations;  // pairs, in order
  std::string config, trajectory;
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

nlohmann::json errors_json(const RelationErrors& all, const RelationErrors& short_span, double max_span) {
  return {{"translational_error_m", stats_json(all.translational, 1)},
          {"rotational_error_deg", stats_json(all.rotational, 180 / M_PI)},
          {"relations", all.translational.count},
          {"relations_missing", all.missing},
          {"short_relations",
           {{"max_span_s", max_span},
            {"relations", short_span.translational.count},
            {"translational_error_m", stats_json(short_span.translational, 1)},
            {"rotational_error_deg", stats_json(short_span.rotational, 180 / M_PI)}}}};
}

void print_errors(const RelationErrors& all, const RelationErrors& short_span, double max_span) {
  auto line = [](const char* name, const RelationErrors& e) {
    std::printf("%s: %zu relations, translational %.3f +- %.3f m (max %.3f), rotational %.2f +- %.2f deg (max %.2f)\n",
                name, e.translational.count, e.translational.mean, e.translational.std, e.translational.max,
                e.rotational.mean * 180 / M_PI, e.rotational.std * 180 / M_PI, e.rotational.max * 180 / M_PI);
  };
  line("all relations", all);
  char name[64];
  std::snprintf(name, sizeof(name), "relations within %.0f s", max_span);
  line(name, short_span);
  if (all.missing) std::printf("%zu relations name a scan without a pose\n", all.missing);
}

// The Freiburg metric over all relations and over those within max_span, as text or one
// JSON object (with `extra` merged in).
void print_scores(const Trajectory& trajectory, const std::vector<Relation>& relations, double max_span, bool json,
                  nlohmann::json extra) {
  const RelationErrors all = evaluate_relations(trajectory.stamps, trajectory.poses, relations);
  const RelationErrors short_span = evaluate_relations(trajectory.stamps, trajectory.poses, relations, max_span);
  if (json) {
    extra.update(errors_json(all, short_span, max_span));
    std::cout << extra << "\n";
    return;
  }
  print_errors(all, short_span, max_span);
}

// One row per log and the mean of the logs' means (each log counts once, whatever its
// number of relations), all relations and the short ones.
void print_table(const std::vector<std::string>& logs, const std::vector<LogScore>& scores, double max_span) {
  std::printf("%-28s %9s %14s %14s %12s %12s %9s\n", "log", "relations", "all (m)", "short (m)", "all (deg)",
              "short (deg)", "scans/s");
  double sums[4] = {0, 0, 0, 0};
  for (size_t i = 0; i < logs.size(); ++i) {
    const LogScore& s = scores[i];
    const double row[4] = {s.all.translational.mean, s.short_span.translational.mean,
                           s.all.rotational.mean * 180 / M_PI, s.short_span.rotational.mean * 180 / M_PI};
    std::printf("%-28s %9zu %14.3f %14.3f %12.2f %12.2f %9.0f\n", logs[i].substr(logs[i].find_last_of('/') + 1).c_str(),
                s.all.translational.count, row[0], row[1], row[2], row[3], s.scans_per_second);
    for (int k = 0; k < 4; ++k) sums[k] += row[k];
  }
  const double n = static_cast<double>(logs.size());
  std::printf("%-28s %9s %14.3f %14.3f %12.2f %12.2f  (short: within %.0f s)\n", "mean of the logs", "", sums[0] / n,
              sums[1] / n, sums[2] / n, sums[3] / n, max_span);
}

int run_eval(const EvalOptions& options) {
  if (options.logs.size() != options.relations.size()) {
    std::cerr << "scanbus scanmatch eval: " << options.logs.size() << " --log and " << options.relations.size()
              << " --relations: give them in pairs\n";
    return 2;
  }
  if (options.logs.size() > 1 && !options.trajectory.empty()) {
    std::cerr << "scanbus scanmatch eval: --trajectory takes one log\n";
    return 2;
  }
  MatcherSettings settings;
  try {
    settings = load_matcher_settings(options.config);
  } catch (const std::runtime_error& e) {  // ConfigError
    std::cerr << "scanbus scanmatch eval: " << e.what() << "\n";
    return 2;
  }
  const bool progress = !options.json && isatty(STDOUT_FILENO);
  std::vector<LogScore> scores;
  nlohmann::json json_logs = nlohmann::json::array();
  for (size_t i = 0; i < options.logs.size(); ++i) {
    const std::string& log = options.logs[i];
    std::vector<LaserRecord> records;
    std::vector<Relation> relations;
    try {
      records = load_laser_log(log);
      relations = read_relations(options.relations[i]);
    } catch (const std::runtime_error& e) {  // LogError
      std::cerr << "scanbus scanmatch eval: " << e.what() << "\n";
      return 2;
    }
    if (options.odometry_guess && std::all_of(records.begin(), records.end(), [](const LaserRecord& r) {
          return r.odometry.x == 0 && r.odometry.y == 0 && r.odometry.theta == 0;
        })) {
      std::cerr << "scanbus scanmatch eval: " << log << " carries no odometry for --odometry-guess\n";
      return 2;
    }
    scores.push_back(score_log(
        settings, records, relations, options.odometry_guess, options.max_span, [&](size_t done, size_t total) {
          if (progress && (done % 50 == 1 || done == total))
            std::printf("\rmatching %s: scan %zu of %zu", log.c_str(), done, total), std::fflush(stdout);
        }));
    const LogScore& score = scores.back();
    if (progress) std::printf("\n");
    if (!options.trajectory.empty()) write_trajectory(options.trajectory, score.tracked.trajectory);
    nlohmann::json extra{{"scans", records.size()},
                         {"failed_matches", score.tracked.failed},
                         {"odometry_guess", options.odometry_guess},
                         {"scans_per_second", score.scans_per_second}};
    if (options.json) {
      extra.update(errors_json(score.all, score.short_span, options.max_span));
      extra["log"] = log;
      json_logs.push_back(extra);
      continue;
    }
    if (options.logs.size() > 1) std::printf("%s:\n", log.c_str());
    print_errors(score.all, score.short_span, options.max_span);
    std::printf("%zu scans, %zu failed matches, %.0f scans per second%s\n", records.size(), score.tracked.failed,
                score.scans_per_second, options.odometry_guess ? ", odometry as initial guess" : "");
  }
  if (options.json)
    std::cout << (json_logs.size() == 1 ? json_logs[0] : nlohmann::json{{"logs", json_logs}}) << "\n";
  else if (options.logs.size() > 1)
    print_table(options.logs, scores, options.max_span);
  return 0;
}

struct ScoreOptions {
  std::string trajectory, relations;
  double max_span = 10.0;
  bool json = false;
};

// A trajectory from elsewhere (the scan_matcher service's rt/scan_match, say) scored
// against relations as `eval` scores its own.
int run_score(const ScoreOptions& options) {
  Trajectory trajectory;
  std::vector<Relation> relations;
  try {
    relations = read_relations(options.relations);
    trajectory = read_trajectory(options.trajectory);
  } catch (const LogError& e) {
    std::cerr << "scanbus scanmatch score: " << e.what() << "\n";
    return 2;
  }
  print_scores(trajectory, relations, options.max_span, options.json, {{"poses", trajectory.poses.size()}});
  return 0;
}

struct ConvertOptions {
  std::string log, out, frame = "laser";
};

int run_convert(const ConvertOptions& options) {
  std::vector<LaserRecord> records;
  try {
    records = read_carmen_log(options.log);
  } catch (const LogError& e) {
    std::cerr << "scanbus scanmatch convert: " << e.what() << "\n";
    return 2;
  }
  write_laser_mcap(options.out, records, options.frame);
  std::printf("wrote %s: %zu LaserScan messages on /scan\n", options.out.c_str(), records.size());
  return 0;
}

struct BacktransformOptions {
  std::string log, config, out;
  long row = -1;  // the pair (row, row + 1); -1 with --all
  bool all = false, json = false, odometry_guess = false;
  double max_median = 0.02;  // m: a pair whose median nearest-point distance is larger than this
                             // plus half its rays' spacing is suspect (a SICK's range noise and
                             // systematic error; docs/performance.md has both Freiburg logs)
};

nlohmann::json pair_json(const PairCheck& check) {
  const Pose2& i = check.increment;
  return {{"row", check.row},
          {"increment", {{"x", i.x}, {"y", i.y}, {"theta_deg", i.theta * 180 / M_PI}}},
          {"quality", static_cast<int>(check.quality)},
          {"residual_median_m", check.median},
          {"residual_p90_m", check.p90},
          {"spacing_m", check.spacing},
          {"points", check.points},
          {"verdict", check.suspect ? "suspect" : "ok"}};
}

std::string pair_line(const PairCheck& check) {
  const Pose2& i = check.increment;
  char line[200];
  std::snprintf(line, sizeof(line),
                "scans %zu-%zu: increment %.3f %.3f m %.2f deg, residual median %.4f m, p90 %.4f m over %zu points: %s",
                check.row, check.row + 1, i.x, i.y, i.theta * 180 / M_PI, check.median, check.p90, check.points,
                check.suspect ? "SUSPECT" : "ok");
  return line;
}

int run_backtransform(const BacktransformOptions& options) {
  std::vector<LaserRecord> records;
  MatcherSettings settings;
  try {
    settings = load_matcher_settings(options.config);
    records = load_laser_log(options.log);
  } catch (const std::runtime_error& e) {  // LogError, ConfigError
    std::cerr << "scanbus scanmatch backtransform: " << e.what() << "\n";
    return 2;
  }
  if (!options.all && (options.row < 0 || static_cast<size_t>(options.row) + 1 >= records.size())) {
    std::cerr << "scanbus scanmatch backtransform: --row " << options.row
              << " is not a scan with a successor: " << options.log << " has scans 0 to " << records.size() - 1 << "\n";
    return 2;
  }
  // The increments are the running matcher's over the log up to the pair, as the service made them.
  const size_t rows = options.all ? records.size() : static_cast<size_t>(options.row) + 2;
  const std::vector<LaserRecord> tracked(records.begin(), records.begin() + static_cast<long>(rows));
  const bool progress = !options.json && isatty(STDOUT_FILENO);
  const auto checks =
      check_log(settings, tracked, options.odometry_guess, options.max_median, [&](size_t done, size_t total) {
        if (progress && (done % 200 == 0 || done == total))
          std::printf("\rtracking: scan %zu of %zu", done, total), std::fflush(stdout);
      });
  if (progress) std::printf("\r\033[K");
  if (!options.all) {
    const PairCheck& check = checks.back();
    if (!options.out.empty()) {
      const ScanMatcher matcher(settings);
      const auto reference = matcher.points_of(records[check.row].scan);
      const auto moved = carried_back(matcher.points_of(records[check.row + 1].scan), check.increment);
      char title[96];
      std::snprintf(title, sizeof(title), "BacktransformLaserScan: scan %zu+1 onto scan %zu", check.row, check.row);
      plot::write_backtransform_picture(options.out, reference, moved, title, pair_line(check));
    }
    std::cout << (options.json ? pair_json(check).dump() : pair_line(check)) << "\n";
    return check.suspect ? 1 : 0;
  }
  size_t suspect = 0;
  std::vector<double> medians;
  for (const auto& check : checks) {
    suspect += check.suspect;
    medians.push_back(check.median);
  }
  if (options.json) {
    nlohmann::json pairs = nlohmann::json::array();
    for (const auto& check : checks) pairs.push_back(pair_json(check));
    std::cout << nlohmann::json{{"pairs", pairs},
                                {"suspect", suspect},
                                {"max_median_m", options.max_median},
                                {"median_of_medians_m", percentile(medians, 0.5)}}
              << "\n";
  } else {
    for (const auto& check : checks)
      if (check.suspect) std::cout << pair_line(check) << "\n";
    std::printf(
        "%zu pairs, %zu suspect (median residual over %.3f m and half the spacing, or a failed match), "
        "median residual %.4f m\n",
        checks.size(), suspect, options.max_median, percentile(medians, 0.5));
  }
  return 0;
}

}  // namespace

void add_scanmatch_command(CLI::App& app, int& exit_code) {
  static EvalOptions options;
  auto* scanmatch = app.add_subcommand("scanmatch", "Laser scan matching (PL-ICP)");
  scanmatch->require_subcommand(1);
  auto* eval = scanmatch->add_subcommand("eval", "Match a CARMEN log's scans and score them against relations");
  eval->add_option("--log", options.logs,
                   "CARMEN log (FLASER or ROBOTLASER1 lines), or an MCAP recording of /scan; several, each with "
                   "its --relations in the same order, give one row per log and the mean")
      ->required();
  eval->add_option("--relations", options.relations, "Relations file (t1 t2 x y z roll pitch yaw), one per --log")
      ->required();
  eval->add_option("--config", options.config, "Service file with a scan_matcher.matcher section (default: built-in)");
  eval->add_option("--trajectory", options.trajectory, "Write the matched poses, one 'stamp x y theta' line per scan");
  eval->add_flag("--odometry-guess", options.odometry_guess, "Use wheel odometry as each match's initial guess");
  eval->add_option("--max-span", options.max_span, "Also report relations at most this many seconds apart");
  eval->add_flag("--json", options.json, "Print one JSON object");
  on_run(*eval, exit_code, [] { return run_eval(options); });

  static ScoreOptions score;
  auto* scorer = scanmatch->add_subcommand("score", "Score a trajectory ('stamp x y theta' lines) against relations");
  scorer->add_option("--trajectory", score.trajectory, "Poses, one 'stamp x y theta' line each")->required();
  scorer->add_option("--relations", score.relations, "Relations file (t1 t2 x y z roll pitch yaw)")->required();
  scorer->add_option("--max-span", score.max_span, "Also report relations at most this many seconds apart");
  scorer->add_flag("--json", score.json, "Print one JSON object");
  on_run(*scorer, exit_code, [] { return run_score(score); });

  static ConvertOptions convert;
  auto* converter = scanmatch->add_subcommand("convert", "Convert a CARMEN log's scans to an MCAP recording of /scan");
  converter->add_option("--log", convert.log, "CARMEN log (FLASER or ROBOTLASER1 lines)")->required();
  converter->add_option("--out", convert.out, "MCAP file to write")->required();
  converter->add_option("--frame", convert.frame, "LaserScan frame_id");
  on_run(*converter, exit_code, [] { return run_convert(convert); });

  static BacktransformOptions back;
  auto* backtransform = scanmatch->add_subcommand(
      "backtransform",
      "BacktransformLaserScan: carry scan N+1 back onto scan N by the running matcher's increment and measure the fit");
  backtransform
      ->add_option("--log", back.log, "CARMEN log (FLASER or ROBOTLASER1 lines), or an MCAP recording of /scan")
      ->required();
  auto* row = backtransform->add_option("--row", back.row, "The pair (N, N+1), scans counted from 0");
  auto* all = backtransform->add_flag("--all", back.all, "Check every consecutive pair; list the suspect ones");
  row->excludes(all);
  backtransform->add_option("--out", back.out, "PNG picture of the pair (with --row)")->excludes(all);
  backtransform->add_option(
      "--max-median", back.max_median,
      "m: a median nearest-point distance larger than this plus half the rays' spacing makes a pair suspect");
  backtransform->add_flag("--odometry-guess", back.odometry_guess, "Track with wheel odometry as the initial guess");
  backtransform->add_option("--config", back.config, "Service file with a scan_matcher.matcher section");
  backtransform->add_flag("--json", back.json, "Print JSON");
  on_run(*backtransform, exit_code, [] { return run_backtransform(back); });
}

}  // namespace scanbus::cli
