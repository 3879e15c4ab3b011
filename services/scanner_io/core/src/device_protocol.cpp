#include "scanbus/scanner_io/device_protocol.hpp"

#include <charconv>
#include <cmath>
#include <vector>

#include "protocol.h"  // the firmware's own checksum: one definition on both ends

namespace scanbus::scanner_io {

namespace {

constexpr double kCentidegree = M_PI / 18000.0;

DeviceLine invalid(std::string why) {
  DeviceLine line;
  line.text = std::move(why);
  return line;
}

std::vector<std::string_view> words(std::string_view text) {
  std::vector<std::string_view> out;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = text.find(' ', start);
    const size_t stop = end == std::string_view::npos ? text.size() : end;
    if (stop > start) out.push_back(text.substr(start, stop - start));
    start = stop + 1;
  }
  return out;
}

bool to_unsigned(std::string_view word, uint32_t& value) {
  const auto result = std::from_chars(word.data(), word.data() + word.size(), value);
  return result.ec == std::errc() && result.ptr == word.data() + word.size();
}

bool to_double(std::string_view word, double& value) {
  // from_chars for double needs GCC 11; bookworm has 12.
  const auto result = std::from_chars(word.data(), word.data() + word.size(), value);
  return result.ec == std::errc() && result.ptr == word.data() + word.size() && std::isfinite(value);
}

// Numeric fields after the tag; false when there are not exactly `count` of them.
bool fields(const std::vector<std::string_view>& parts, size_t count, uint32_t* out) {
  if (parts.size() != count + 1) return false;
  for (size_t i = 0; i < count; ++i)
    if (!to_unsigned(parts[i + 1], out[i])) return false;
  return true;
}

DeviceLine parse_scanbus(std::string_view line) {
  const size_t star = line.rfind('*');
  if (star == std::string_view::npos || star + 3 != line.size()) return invalid("no checksum");
  uint32_t sum = 0;
  const auto hex = line.substr(star + 1);
  if (std::from_chars(hex.data(), hex.data() + 2, sum, 16).ptr != hex.data() + 2) return invalid("bad checksum field");
  if (sum != scanner::checksum(line.data(), static_cast<int>(star))) {
    DeviceLine bad = invalid("checksum mismatch");
    bad.bad_checksum = true;
    return bad;
  }
  const auto parts = words(line.substr(0, star));
  if (parts.empty() || parts[0].size() != 1) return invalid("no tag");
  DeviceLine out;
  uint32_t v[6];
  switch (parts[0][0]) {
    case 'M':
      if (!fields(parts, 5, v)) return invalid("measurement needs 5 numbers");
      out.kind = LineKind::Measurement;
      out.measurement.line = v[0];
      out.measurement.yaw = v[1] * kCentidegree;
      out.measurement.pitch = v[2] * kCentidegree;
      out.measurement.range = v[3] / 100.0;
      out.measurement.signal = v[4];
      if (out.measurement.pitch > M_PI) return invalid("pitch beyond 180 degrees");
      return out;
    case 'L':
      if (!fields(parts, 2, v)) return invalid("lap needs 2 numbers");
      out.kind = LineKind::Lap;
      out.counted = true;
      out.revolution = v[0];
      out.pitch = v[1] * kCentidegree;
      return out;
    case 'D':
      if (!fields(parts, 2, v)) return invalid("done needs 2 numbers");
      out.kind = LineKind::Done;
      out.counted = true;
      out.cycle = v[0];
      out.revolution = v[1];
      return out;
    case 'S':
      if (!fields(parts, 6, v)) return invalid("status needs 6 numbers");
      out.kind = LineKind::Status;
      out.status = {static_cast<uint8_t>(v[0]), static_cast<uint8_t>(v[1]), v[2] / 10.0, v[3], v[4], v[5]};
      return out;
    case 'E':
      if (parts.size() != 3 || !to_unsigned(parts[1], v[0])) return invalid("error needs a code and a word");
      out.kind = LineKind::DeviceError;
      out.error_code = static_cast<int>(v[0]);
      out.text = std::string(parts[2]);
      return out;
    case 'H':
      if (parts.size() != 4 || parts[1] != "scanbus-scanner" || !to_unsigned(parts[2], v[0]))
        return invalid("hello needs 'scanbus-scanner VERSION FIRMWARE'");
      out.kind = LineKind::Hello;
      out.protocol_version = static_cast<int>(v[0]);
      out.text = std::string(parts[3]);
      return out;
  }
  return invalid("unknown tag");
}

DeviceLine parse_legacy(std::string_view line) {
  DeviceLine out;
  if (line == "n") {
    out.kind = LineKind::Lap;
    return out;
  }
  if (line == "d") {
    out.kind = LineKind::Done;
    return out;
  }
  const auto parts = words(line);
  double pitch = 0, yaw = 0, range_cm = 0;
  if (parts.size() != 3 || !to_double(parts[0], pitch) || !to_double(parts[1], yaw) || !to_double(parts[2], range_cm))
    return invalid("legacy line needs 'phi theta rho'");
  if (pitch < 0 || pitch > M_PI) return invalid("pitch outside 0..pi");
  if (range_cm < 0) return invalid("negative range");
  out.kind = LineKind::Measurement;
  out.measurement.pitch = pitch;
  out.measurement.yaw = yaw;
  out.measurement.range = range_cm / 100.0;  // the thesis sends centimetres
  return out;
}

}  // namespace

DeviceLine parse_line(std::string_view line, Dialect dialect) {
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.remove_suffix(1);
  if (line.empty()) return invalid("empty line");
  return dialect == Dialect::Scanbus ? parse_scanbus(line) : parse_legacy(line);
}

}  // namespace scanbus::scanner_io
