#include "scanbus/scanner_io/scan_assembler.hpp"

namespace scanbus::scanner_io {

ScanOutput ScanAssembler::add(const DeviceLine& line, double now) {
  ++counters_.lines;
  ScanOutput out;
  switch (line.kind) {
    case LineKind::Invalid:
      ++(line.bad_checksum ? counters_.checksum_errors : counters_.malformed_lines);
      break;
    case LineKind::Hello:  // the device (re)started: sequence numbers begin again
      abort();
      expected_sequence_.reset();
      break;
    case LineKind::Measurement: {
      if (line.measurement.line != 0 || expected_sequence_) {
        expect_next(line.measurement.line);
        expected_sequence_ = line.measurement.line + 1;
      }
      SphericalMeasurement measurement = line.measurement;
      measurement.stamp = now;
      ++counters_.measurements;
      current_.measurements.push_back(measurement);
      if (in_gate(measurement, gate_)) {
        current_.points.push_back({to_cartesian(measurement.range, measurement.yaw, measurement.pitch),
                                   static_cast<float>(measurement.signal)});
      } else {
        ++counters_.out_of_range;
      }
      break;
    }
    case LineKind::Lap:
      if (line.counted && line.revolution == 0 && laps_in_scan_ > 0) {
        // A new scan began though the last one's end never came: that one is lost, this
        // one's first revolution (just measured) is not.
        Revolution first = std::move(current_);
        abort();
        current_ = std::move(first);
      }
      if (line.counted) current_.index = line.revolution;
      // The thesis firmware's 'n' also comes before the first revolution: nothing to close.
      if (line.counted || !current_.measurements.empty()) out.revolution = close_revolution();
      break;
    case LineKind::Done:
      if (line.counted && laps_in_scan_ != line.revolution) {
        abort();  // joined mid-scan or lost laps: not a whole scan
        break;
      }
      // Thesis lines end the last revolution with 'd' alone.
      if (!current_.measurements.empty()) out.revolution = close_revolution();
      out.scan = std::move(scan_points_);
      out.scan_lost_lines = scan_lost_lines_;
      scan_points_.clear();
      scan_lost_lines_ = 0;
      current_ = Revolution{};
      laps_in_scan_ = 0;
      ++scan_index_;
      ++counters_.scans;
      break;
    case LineKind::Status:  // the device's next sequence number: lines lost before it count too,
                            // as do the first ones after a (re)connect
      expect_next(line.status.sequence);
      break;
    case LineKind::DeviceError:
      break;
  }
  return out;
}

Revolution ScanAssembler::close_revolution() {
  ++laps_in_scan_;
  ++counters_.revolutions;
  current_.scan = scan_index_;
  scan_points_.insert(scan_points_.end(), current_.points.begin(), current_.points.end());
  scan_lost_lines_ += current_.lost;
  Revolution closed = std::move(current_);
  current_ = Revolution{};
  current_.index = closed.index + 1;
  return closed;
}

void ScanAssembler::expect_next(uint32_t next) {
  if (expected_sequence_ && next <= *expected_sequence_) return;  // nothing skipped
  if (expected_sequence_) {
    const uint64_t gap = next - *expected_sequence_;
    counters_.lost_lines += gap;
    current_.lost += gap;
  }
  expected_sequence_ = next;
}

void ScanAssembler::abort() {
  if (scanning() || laps_in_scan_ > 0) ++counters_.aborted_scans;
  current_ = Revolution{};
  scan_points_.clear();
  scan_lost_lines_ = 0;
  laps_in_scan_ = 0;
}

}  // namespace scanbus::scanner_io
