// Lines from the scanner, parsed into SI units. Two dialects:
// - scanbus (firmware/PROTOCOL.md): checksummed, sequence-numbered lines;
// - legacy: the thesis firmware's "phi theta rho" lines (pitch and yaw in radians with two
//   decimals, range in integer centimetres), "n" for a new lap and "d" for done.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "scanbus/scanner_io/spherical.hpp"

namespace scanbus::scanner_io {

enum class LineKind { Hello, Measurement, Lap, Done, Status, DeviceError, Invalid };

enum class Dialect { Scanbus, Legacy };

struct DeviceStatus {
  uint8_t state = 0;
  uint8_t resolution = 0;
  double rpm = 0;
  uint32_t revolution = 0;
  uint32_t sequence = 0;
  uint32_t cycle = 0;
};

struct DeviceLine {
  LineKind kind = LineKind::Invalid;
  SphericalMeasurement measurement;  // Measurement
  uint32_t revolution = 0;           // Lap: revolution just completed; Done: revolutions in the scan
  bool counted = false;              // Lap and Done carry the device's counts (not legacy lines)
  double pitch = 0;                  // Lap: its pitch, rad
  uint32_t cycle = 0;                // Done
  DeviceStatus status;               // Status
  int protocol_version = 0;          // Hello
  std::string text;                  // Hello: firmware version; DeviceError: the word; Invalid: why
  int error_code = 0;                // DeviceError
  bool bad_checksum = false;         // Invalid because of the checksum
};

DeviceLine parse_line(std::string_view line, Dialect dialect);

}  // namespace scanbus::scanner_io
