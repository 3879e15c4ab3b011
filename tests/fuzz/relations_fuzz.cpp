// Relation files of the Freiburg SLAM benchmark, as `scanbus scanmatch eval` reads them.
#include "fuzz_input.hpp"
#include "scanbus/scan_matcher/laser_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const scanbus::fuzz::InputFile file(data, size, "relations");
  try {
    scanbus::scan_matcher::read_relations(file.path());
  } catch (const scanbus::scan_matcher::LogError&) {
  }
  return 0;
}
