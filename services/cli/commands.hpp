// Subcommands of the `scanbus` command line, each registered on the CLI11 app.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <functional>
#include <string>

#include "scanbus/dds.hpp"

namespace scanbus::cli {

// Options every DDS-using subcommand shares.
struct DdsOptions {
  std::string profile_file;  // empty: the built-in loopback profile
  int domain = 0;

  std::string profile = "localhost";  // participant profile name in that file

  DdsSettings settings() const { return {profile_file, profile, domain}; }
};
void add_dds_options(CLI::App& command, DdsOptions& options);

// Runs `body` when the subcommand is chosen; its return value becomes the exit code, and
// an exception becomes one "scanbus NAME: what" line on stderr and exit code 1.
void on_run(CLI::App& command, int& exit_code, std::function<int()> body);

// Each adds its subcommand; the callback stores the exit code in `exit_code`.
void add_topics_command(CLI::App& app, int& exit_code);
void add_security_command(CLI::App& app, int& exit_code);
void add_echo_command(CLI::App& app, int& exit_code);
void add_health_command(CLI::App& app, int& exit_code);
void add_run_command(CLI::App& app, int& exit_code);
void add_demo_command(CLI::App& app, int& exit_code);
void add_scan_command(CLI::App& app, int& exit_code);
void add_sim_command(CLI::App& app, int& exit_code);
void add_room_command(CLI::App& app, int& exit_code);
void add_scanmatch_command(CLI::App& app, int& exit_code);
void add_mav_sim_command(CLI::App& sim, int& exit_code);  // `sim mav`, under add_sim_command's `sim`
void add_eval_command(CLI::App& app, int& exit_code);
void add_calibrate_command(CLI::App& app, int& exit_code);    // the MAV laser's scan plane from a hover-turn
void add_eval_rooms_command(CLI::App& eval, int& exit_code);  // `eval rooms`, under add_eval_command's `eval`
void add_cloud_command(CLI::App& app, int& exit_code);
void add_record_commands(CLI::App& app, int& exit_code);  // record, replay, info

}  // namespace scanbus::cli
