// The scanner simulator's main loop, shared by scanbus_scanner_sim and `scanbus sim scanner`.
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace scanbus::sim {

struct ScannerSimOptions {
  std::string room_file;  // empty: the built-in thesis case 1 room
  std::string link;       // symlink to the pty, if set
  double speed = 1.0;     // times real time
  unsigned seed = 1;
  double noise = 0.02;  // m
  double dropout = 0.002;
  double unplug_at = -1;    // s of simulated time; negative: never
  double unplug_for = 2.0;  // s of real time
};

void add_scanner_sim_options(CLI::App& app, ScannerSimOptions& options);

// Runs until SIGINT or SIGTERM. Exit codes: 0, 1 failure, 2 bad room file.
int run_scanner_sim(const ScannerSimOptions& options);

}  // namespace scanbus::sim
