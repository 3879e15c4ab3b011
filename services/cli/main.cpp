// scanbus: one command for the whole stack (see `scanbus --help`).
#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"scanbus: LiDAR point clouds, poses and room measurements over DDS"};
  app.require_subcommand(1);
  int exit_code = 0;
  scanbus::cli::add_topics_command(app, exit_code);
  scanbus::cli::add_security_command(app, exit_code);
  scanbus::cli::add_echo_command(app, exit_code);
  scanbus::cli::add_health_command(app, exit_code);
  scanbus::cli::add_run_command(app, exit_code);
  scanbus::cli::add_demo_command(app, exit_code);
  scanbus::cli::add_scan_command(app, exit_code);
  scanbus::cli::add_sim_command(app, exit_code);
  scanbus::cli::add_room_command(app, exit_code);
  scanbus::cli::add_scanmatch_command(app, exit_code);
  scanbus::cli::add_eval_command(app, exit_code);
  scanbus::cli::add_calibrate_command(app, exit_code);
  scanbus::cli::add_cloud_command(app, exit_code);
  scanbus::cli::add_record_commands(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return exit_code;
}
