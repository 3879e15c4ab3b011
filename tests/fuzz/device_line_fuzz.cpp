// The host's reading of the scanner's serial lines (both dialects, scanner_io's
// device_protocol) and the scan assembler fed whatever they parse to.
#include <cmath>
#include <string_view>

#include "fuzz_input.hpp"
#include "scanbus/scanner_io/device_protocol.hpp"
#include "scanbus/scanner_io/scan_assembler.hpp"

using namespace scanbus::scanner_io;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (const Dialect dialect : {Dialect::Scanbus, Dialect::Legacy}) {
    ScanAssembler assembler(RangeGate{});
    double now = 0;
    size_t start = 0;
    while (start <= text.size()) {
      const size_t end = std::min(text.find('\n', start), text.size());
      const DeviceLine line = parse_line(text.substr(start, end - start), dialect);
      if (line.kind == LineKind::Measurement) {
        const auto& m = line.measurement;
        scanbus::fuzz::require(std::isfinite(m.range) && std::isfinite(m.yaw) && std::isfinite(m.pitch));
      }
      assembler.add(line, now += 0.001);
      start = end + 1;
    }
  }
  return 0;
}
