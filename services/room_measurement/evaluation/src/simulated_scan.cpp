#include "scanbus/room_evaluation/simulated_scan.hpp"

#include <sstream>
#include <stdexcept>

#include "scanbus/scanner_io/scan_assembler.hpp"
#include "scanbus/sim/simulated_hardware.hpp"
#include "scanner_core.h"

namespace scanbus::room_evaluation {

std::vector<Eigen::Vector3f> simulated_scan(const sim::RoomModel& room, const SimulatedScanSettings& settings) {
  sim::SimulatedHardware hardware(
      [&room](const Eigen::Vector3d& o, const Eigen::Vector3d& d) { return room.cast(o, d); }, settings.hardware);
  scanner::ScannerCore core(hardware);
  core.begin();
  scanner_io::ScanAssembler assembler(scanner_io::RangeGate{});
  std::vector<Eigen::Vector3f> points;
  std::string pending;
  for (int cycle = 0; cycle < settings.cycles; ++cycle) {
    hardware.feed_input("RES " + std::to_string(settings.resolution) + "\nSTART\n");
    bool done = false;
    for (int step = 0; step < 2000000 && !done; ++step) {
      core.poll();
      hardware.advance(0.0005);
      pending += hardware.take_output();
      size_t end;
      while ((end = pending.find('\n')) != std::string::npos) {
        const auto output =
            assembler.add(scanner_io::parse_line(pending.substr(0, end), scanner_io::Dialect::Scanbus), 0);
        pending.erase(0, end + 1);
        if (output.scan) {
          for (const auto& point : *output.scan) points.push_back(point.position);
          done = true;
        }
      }
    }
    if (!done) throw std::runtime_error("simulated scan did not finish");
  }
  return points;
}

}  // namespace scanbus::room_evaluation
