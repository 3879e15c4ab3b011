// The MAV text log (docs/mav_log.md), as `scanbus eval mav --log` and sensor_replay read it,
// the records put in time order as the replay does, and the true ground a simulated log
// carries (META scenario, boxes, terrain_*) rebuilt and sampled as `scanbus eval mav` does.
#include "fuzz_input.hpp"
#include "scanbus/mav_sim/flight.hpp"
#include "scanbus/sensor_replay/mav_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const scanbus::fuzz::InputFile file(data, size, "mavlog");
  try {
    const auto log = scanbus::sensor_replay::read_mav_log(file.path());
    scanbus::sensor_replay::records_in_time_order(log);
    if (const auto world = scanbus::mav_sim::world_of_log(log)) {
      world->scored_height({1, 0.5}, 0.1);
      world->cast({1, 0.5, 3}, {0.3, 0, -0.954});
    }
  } catch (const scanbus::sensor_replay::MavLogError&) {
  }
  return 0;
}
