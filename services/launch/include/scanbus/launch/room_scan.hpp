// Full scans of a simulated room through the real path: the firmware simulator on a pty,
// scanner_io reading it and, when asked, room_measurement, each a separate process; the
// clouds and the measurement back over DDS.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "scanbus/cloud_point.hpp"
#include "scanbus/dds.hpp"
#include "scanbus/launch/system.hpp"
#include "scanbus_msgs/RoomMeasurement.h"

namespace scanbus::launch {

struct RoomScanOptions {
  std::string room_file;  // empty: the simulator's built-in room
  double speed = 1.0;
  int resolution = 1;
  bool progress = false;  // a line of progress on the terminal
  double timeout = 600;   // s
  int scans = 1;          // whole scans in a row (each next one interleaves its pitch, eq. 4.9)
  bool measure = false;   // also run room_measurement and wait for its RoomMeasurement
};

struct RoomScanResult {
  std::vector<CloudPoint> points;  // every scan's points
  unsigned revolutions = 0;
  std::optional<scanbus::msg::RoomMeasurement> room;
};

// The processes start in `system` (logs and the pty link in its work folder) and stay
// there, running, until the caller stops it or lets it go. Throws std::runtime_error naming
// what failed (a process that died, with its log).
RoomScanResult run_room_scan(System& system, const RoomScanOptions& options);

}  // namespace scanbus::launch
