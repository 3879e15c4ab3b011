// One full scan of a simulated room through the real path: the firmware simulator on a
// pty, scanner_io reading it as a separate process, the clouds back over DDS.
#pragma once

#include <string>
#include <vector>

#include "commands.hpp"
#include "scanbus/cloud_point.hpp"

namespace scanbus::cli {

struct RoomScanOptions {
  DdsOptions dds;
  std::string room_file;   // empty: the simulator's built-in room
  double speed = 1.0;
  int resolution = 1;
  std::string work_dir;    // logs and the pty link go here
  bool progress = false;   // a line of progress on the terminal
  double timeout = 600;    // s
};

struct RoomScanResult {
  std::vector<CloudPoint> points;
  unsigned revolutions = 0;
};

// Throws std::runtime_error naming what failed (a process that died, with its log).
RoomScanResult run_room_scan(const RoomScanOptions& options);

}  // namespace scanbus::cli
