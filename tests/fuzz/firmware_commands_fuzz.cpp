// The scanner firmware's command reader (firmware/scanner/core) fed the input as host
// commands, a few bytes per poll while the motor turns; every line it writes back must be
// one the host reads as valid (scanner_io's parser, the other side of the protocol).
#include <string>
#include <string_view>

#include "fuzz_input.hpp"
#include "scanbus/scanner_io/device_protocol.hpp"
#include "scanner_core.h"

namespace {

class FuzzHal : public scanner::Hal {
 public:
  FuzzHal(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  uint32_t millis() override { return static_cast<uint32_t>(micros_ / 1000); }
  uint32_t micros() override { return static_cast<uint32_t>(micros_ += 200); }
  int32_t encoder_count() override { return static_cast<int32_t>(micros_ / 20000); }  // about 7 rpm
  uint32_t encoder_edge_micros() override { return static_cast<uint32_t>(micros_ / 20000 * 20000); }
  void set_motor(uint8_t) override {}
  void set_servo_degrees(uint8_t) override {}
  bool measure(uint16_t& range_cm, uint8_t& signal) override {
    range_cm = static_cast<uint16_t>(100 + micros_ % 1000);
    signal = 200;
    return micros_ % 7 != 0;  // now and then the LiDAR does not answer
  }
  void write(const char* text) override {
    for (std::string_view rest(text); !rest.empty();) {
      const size_t end = rest.find('\n');
      pending_.append(rest.substr(0, end));
      if (end == std::string_view::npos) break;
      const auto line = scanbus::scanner_io::parse_line(pending_, scanbus::scanner_io::Dialect::Scanbus);
      scanbus::fuzz::require(line.kind != scanbus::scanner_io::LineKind::Invalid);
      pending_.clear();
      rest.remove_prefix(end + 1);
    }
  }
  int read() override {
    if (offset_ >= size_ || burst_ == 0) return -1;
    --burst_;
    return data_[offset_++];
  }
  bool done() const { return offset_ >= size_; }
  void next_poll() { burst_ = 8; }

 private:
  const uint8_t* data_;
  size_t size_, offset_ = 0;
  int burst_ = 0;
  uint64_t micros_ = 0;
  std::string pending_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzHal hal(data, size);
  scanner::ScannerCore core(hal);
  core.begin();
  for (int polls = 0; !hal.done() || polls < 200; ++polls) {
    hal.next_poll();
    core.poll();
  }
  return 0;
}
