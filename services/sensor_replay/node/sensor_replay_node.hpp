#pragma once

#include "scanbus/service.hpp"

namespace scanbus::sensor_replay {

// Config section `sensor_replay` (config/services/sensor_replay.yaml lists every key):
// a MAV log (docs/mav_log.md) published on rt/scan, rt/imu, rt/fix, rt/pressure and, with
// its truth, rt/truth/pose, at `rate` times real time (0: as fast as possible).
std::unique_ptr<Service> make_sensor_replay(ServiceContext& context);

}  // namespace scanbus::sensor_replay
