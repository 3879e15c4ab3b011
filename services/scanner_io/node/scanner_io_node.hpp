#pragma once

#include "scanbus/service.hpp"

namespace scanbus::scanner_io {

// Config section `scanner_io` (all optional; config/services/scanner_io.yaml lists them):
//   port: /dev/ttyACM0        # serial device or pty (the simulator prints or links one)
//   baud: 115200              # 9600, 19200, 38400, 57600, 115200, 230400
//   protocol: scanbus         # scanbus (firmware/PROTOCOL.md) or legacy (thesis lines)
//   autostart: true           # on hello: set the resolution and START a scan
//   resolution: 1             # Table 4.2: 0 = 12 RPM, 1 = 20 RPM, 2 = 28 RPM
//   scans: 1                  # scans to start in a row (0 = keep scanning)
//   reconnect_min: 0.2        # s, first retry after the device is lost; a missing device
//                             #   node is looked for this often, so a replug is taken up at once
//   reconnect_max: 5.0        # s, back-off doubles up to this
//   min_range: 0.05           # m, nearer returns are not put in clouds
//   max_range: 40.0           # m
//   frame_id: scanner
std::unique_ptr<Service> make_scanner_io(ServiceContext& context);

}  // namespace scanbus::scanner_io
