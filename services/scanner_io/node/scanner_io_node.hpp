#pragma once

#include "scanbus/service.hpp"

namespace scanbus::scanner_io {

// Config section `scanner_io` (all optional):
//   source: simulated          # the device stand-in; the serial source comes with the firmware
//   min_range: 0.05            # m, closer returns are dropped
//   max_range: 40.0            # m
//   frame_id: scanner
//   simulated:
//     resolution: 0            # Table 4.2 speed setting: 0 = 12 RPM, 1 = 20 RPM, 2 = 28 RPM
//     rate: 10.0               # times real time; 0 = as fast as possible
//     noise: 0.02              # m, one sigma range noise
//     scans: 1                 # full scans to run (27 revolutions each); 0 = forever
//     seed: 1
std::unique_ptr<Service> make_scanner_io(ServiceContext& context);

}  // namespace scanbus::scanner_io
