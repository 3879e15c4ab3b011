// scanbus_scanner_sim: the scanner's firmware core on simulated hardware in a YAML room, on
// a pseudo-terminal, in real time or faster. Prints "pty PATH" when ready.
#include "scanbus/sim/scanner_sim.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Simulated rotating LiDAR scanner on a pseudo-terminal (firmware core on simulated hardware)"};
  scanbus::sim::ScannerSimOptions options;
  scanbus::sim::add_scanner_sim_options(app, options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return scanbus::sim::run_scanner_sim(options);
}
