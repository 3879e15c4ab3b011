#include "scanbus/sim/scanner_sim.hpp"

#include <signal.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <thread>

#include "scanbus/sim/pty_device.hpp"
#include "scanbus/sim/room_file.hpp"
#include "scanbus/sim/simulated_hardware.hpp"
#include "scanner_core.h"

namespace scanbus::sim {

namespace {

volatile sig_atomic_t stop_requested = 0;
void request_stop(int) { stop_requested = 1; }

constexpr double kPollStep = 0.0005;          // s of simulated time between firmware polls
constexpr size_t kDeviceBufferBytes = 65536;  // unread output beyond this is lost, like a full USB buffer

const char* embedded_room() {
  return
#include "default_room.inc"
      ;
}

// One power-on of the device: hardware state and firmware restart together.
struct Device {
  Device(const RoomModel& room, const ScannerSimOptions& options, unsigned boot)
      : hardware([&room](const Eigen::Vector3d& o, const Eigen::Vector3d& d) { return room.cast(o, d); },
                 settings(options, boot)),
        core(hardware) {
    core.begin();
  }
  static HardwareSettings settings(const ScannerSimOptions& options, unsigned boot) {
    HardwareSettings s;
    s.range_noise = options.noise;
    s.dropout = options.dropout;
    s.seed = options.seed + boot;
    return s;
  }
  SimulatedHardware hardware;
  scanner::ScannerCore core;
};

}  // namespace

int run_scanner_sim_unguarded(const ScannerSimOptions& options) {
  const RoomModel room = options.room_file.empty()
                             ? load_room(scanbus::Config::parse(embedded_room(), "(built-in room)"))
                             : load_room_file(options.room_file);
  signal(SIGINT, request_stop);
  signal(SIGTERM, request_stop);
  signal(SIGPIPE, SIG_IGN);
  auto pty = std::make_unique<PtyDevice>(options.link);
  auto device = std::make_unique<Device>(room, options, 0);
  std::printf("pty %s\n", pty->path().c_str());
  std::fflush(stdout);
  std::fprintf(stderr, "scanner_sim: room '%s', %zu walls, speed x%g\n", room.name.c_str(), room.corners.size(),
               options.speed);

  std::string pending;
  size_t lost_bytes = 0;
  unsigned boots = 0;
  bool unplugged_once = false;
  double sim_offset = 0;  // simulated time before the current boot
  auto started = std::chrono::steady_clock::now();
  while (!stop_requested) {
    const double target =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() * options.speed;
    while (sim_offset + device->hardware.time() < target && !stop_requested) {
      device->core.poll();
      device->hardware.advance(kPollStep);
    }
    pending += device->hardware.take_output();
    if (pending.size() > kDeviceBufferBytes) {  // nobody reading: drop the oldest
      const size_t drop = pending.size() - kDeviceBufferBytes;
      lost_bytes += drop;
      pending.erase(0, drop);
    }
    pending.erase(0, pty->write(pending));
    device->hardware.feed_input(pty->read());

    if (!unplugged_once && options.unplug_at >= 0 && sim_offset + device->hardware.time() >= options.unplug_at) {
      std::fprintf(stderr, "scanner_sim: unplugged at %.1f s for %.1f s\n", options.unplug_at, options.unplug_for);
      unplugged_once = true;
      sim_offset += device->hardware.time();
      pty.reset();
      device.reset();
      pending.clear();
      std::this_thread::sleep_for(std::chrono::duration<double>(options.unplug_for));
      started = std::chrono::steady_clock::now() - std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                       std::chrono::duration<double>(sim_offset / options.speed));
      pty = std::make_unique<PtyDevice>(options.link);
      device = std::make_unique<Device>(room, options, ++boots);
      std::printf("pty %s\n", pty->path().c_str());
      std::fflush(stdout);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (lost_bytes) std::fprintf(stderr, "scanner_sim: %zu bytes lost while no one read the line\n", lost_bytes);
  return 0;
}

int run_scanner_sim(const ScannerSimOptions& options) {
  try {
    return run_scanner_sim_unguarded(options);
  } catch (const ConfigError& e) {
    std::cerr << "scanner_sim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "scanner_sim: " << e.what() << "\n";
    return 1;
  }
}

void add_scanner_sim_options(CLI::App& app, ScannerSimOptions& options) {
  app.add_option("--room", options.room_file, "Room YAML (default: built-in thesis case 1)")->check(CLI::ExistingFile);
  app.add_option("--link", options.link, "Also make this path a symlink to the pty");
  app.add_option("--speed", options.speed, "Times real time")->check(CLI::Range(0.01, 1000.0));
  app.add_option("--seed", options.seed, "Random seed for noise and dropouts");
  app.add_option("--noise", options.noise, "Range noise, one sigma, m")->check(CLI::Range(0.0, 1.0));
  app.add_option("--dropout", options.dropout, "Probability of no return per measurement")->check(CLI::Range(0.0, 1.0));
  app.add_option("--unplug-at", options.unplug_at, "Fault: unplug the device at this simulated time, s");
  app.add_option("--unplug-for", options.unplug_for, "Fault: stay unplugged this long, real s")
      ->check(CLI::Range(0.0, 60.0));
}

}  // namespace scanbus::sim
