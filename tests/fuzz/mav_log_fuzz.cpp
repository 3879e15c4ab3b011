// The MAV text log (docs/mav_log.md), as `scanbus eval mav --log` and sensor_replay read it,
// and the records put in time order as the replay does.
#include "fuzz_input.hpp"
#include "scanbus/sensor_replay/mav_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const scanbus::fuzz::InputFile file(data, size, "mavlog");
  try {
    const auto log = scanbus::sensor_replay::read_mav_log(file.path());
    scanbus::sensor_replay::records_in_time_order(log);
  } catch (const scanbus::sensor_replay::MavLogError&) {
  }
  return 0;
}
