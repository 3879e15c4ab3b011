// CARMEN laser logs (FLASER, ROBOTLASER1), as `scanbus scanmatch` reads them.
#include <cmath>

#include "fuzz_input.hpp"
#include "scanbus/scan_matcher/laser_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const scanbus::fuzz::InputFile file(data, size, "clf");
  try {
    for (const auto& record : scanbus::scan_matcher::read_carmen_log(file.path()))
      scanbus::fuzz::require(std::isfinite(record.scan.stamp) && std::isfinite(record.scan.angle_increment));
  } catch (const scanbus::scan_matcher::LogError&) {
  }
  return 0;
}
