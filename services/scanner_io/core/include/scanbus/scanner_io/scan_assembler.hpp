// Turns the device's lines into revolutions and whole scans, and counts what went wrong:
// lost lines (sequence gaps), bad checksums, malformed lines, ranges outside the gate.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "scanbus/cloud_point.hpp"
#include "scanbus/scanner_io/device_protocol.hpp"
#include "scanbus/scanner_io/spherical.hpp"

namespace scanbus::scanner_io {

struct ScanCounters {
  uint64_t lines = 0;
  uint64_t measurements = 0;
  uint64_t lost_lines = 0;  // sequence numbers that never arrived intact
  uint64_t checksum_errors = 0;
  uint64_t malformed_lines = 0;
  uint64_t out_of_range = 0;  // measurements outside the range gate (kept in SphericalScan, not in clouds)
  uint64_t revolutions = 0;
  uint64_t scans = 0;
  uint64_t aborted_scans = 0;  // device reset or lost mid-scan, or joined mid-scan
};

struct Revolution {
  uint32_t index = 0;
  uint32_t scan = 0;
  std::vector<SphericalMeasurement> measurements;
  std::vector<CloudPoint> points;  // gated, Cartesian, scanner frame
  uint64_t lost = 0;
};

struct ScanOutput {
  std::optional<Revolution> revolution;         // a revolution completed
  std::optional<std::vector<CloudPoint>> scan;  // a whole scan completed
  // Lines of that scan lost on the link (sequence gaps): every lap was seen, but not every
  // measurement, so the cloud has gaps (scanner_io says so in its log). Lines lost after the
  // scan's last measurement show only at the next numbered line, and count there.
  uint64_t scan_lost_lines = 0;
};

class ScanAssembler {
 public:
  explicit ScanAssembler(RangeGate gate) : gate_(gate) {}

  // `now` (s) stamps measurements: the device has no clock of its own.
  ScanOutput add(const DeviceLine& line, double now);
  // The device went away or restarted: the partial scan cannot be completed. A scan is
  // only ever emitted when every one of its laps was seen.
  void abort();

  const ScanCounters& counters() const { return counters_; }
  bool scanning() const { return !current_.measurements.empty() || !scan_points_.empty(); }

 private:
  // `next` is the sequence number the device says comes next (a measurement's own, or a
  // status line's): any skipped since the last are lost. Never moves the expectation back.
  void expect_next(uint32_t next);
  Revolution close_revolution();

  RangeGate gate_;
  ScanCounters counters_;
  Revolution current_;
  std::vector<CloudPoint> scan_points_;
  uint64_t scan_lost_lines_ = 0;
  uint32_t laps_in_scan_ = 0;
  std::optional<uint32_t> expected_sequence_;
  uint32_t scan_index_ = 0;
};

}  // namespace scanbus::scanner_io
