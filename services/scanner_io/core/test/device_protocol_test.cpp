#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "protocol.h"
#include "scanbus/scanner_io/device_protocol.hpp"
#include "scanbus/scanner_io/scan_assembler.hpp"

using namespace scanbus::scanner_io;

namespace {

// A line as the firmware frames it.
std::string framed(const std::string& payload) {
  char line[scanner::kMaxLine];
  payload.copy(line, payload.size());
  scanner::finish_line(line, static_cast<int>(payload.size()));
  return line;
}

// Feeds one framed line to the assembler, at time 1 s.
auto feeder(ScanAssembler& assembler) {
  return [&assembler](const std::string& payload) {
    return assembler.add(parse_line(framed(payload), Dialect::Scanbus), 1.0);
  };
}

}  // namespace

TEST(DeviceProtocol, MeasurementInSiUnits) {
  const DeviceLine line = parse_line(framed("M 17 9000 4200 350 120"), Dialect::Scanbus);
  ASSERT_EQ(line.kind, LineKind::Measurement) << line.text;
  EXPECT_EQ(line.measurement.line, 17u);
  EXPECT_NEAR(line.measurement.yaw, M_PI / 2, 1e-12);
  EXPECT_NEAR(line.measurement.pitch, 42 * M_PI / 180, 1e-12);
  EXPECT_NEAR(line.measurement.range, 3.5, 1e-12);
  EXPECT_EQ(line.measurement.signal, 120);
}

TEST(DeviceProtocol, EveryLineKind) {
  EXPECT_EQ(parse_line(framed("H scanbus-scanner 1 0.1.0"), Dialect::Scanbus).kind, LineKind::Hello);
  const DeviceLine lap = parse_line(framed("L 3 5100"), Dialect::Scanbus);
  EXPECT_EQ(lap.kind, LineKind::Lap);
  EXPECT_EQ(lap.revolution, 3u);
  EXPECT_NEAR(lap.pitch, 51 * M_PI / 180, 1e-12);
  EXPECT_EQ(parse_line(framed("D 0 27"), Dialect::Scanbus).kind, LineKind::Done);
  const DeviceLine status = parse_line(framed("S 2 1 199 4 1000 0"), Dialect::Scanbus);
  EXPECT_EQ(status.kind, LineKind::Status);
  EXPECT_NEAR(status.status.rpm, 19.9, 1e-12);
  const DeviceLine error = parse_line(framed("E 1 unknown-command"), Dialect::Scanbus);
  EXPECT_EQ(error.kind, LineKind::DeviceError);
  EXPECT_EQ(error.text, "unknown-command");
}

TEST(DeviceProtocol, DamagedLinesAreInvalidNeverFatal) {
  std::string corrupted = framed("M 17 9000 4200 350 120");
  corrupted[3] = '8';
  EXPECT_TRUE(parse_line(corrupted, Dialect::Scanbus).bad_checksum);
  EXPECT_EQ(parse_line("M 17 9000 4200 350 120", Dialect::Scanbus).text, "no checksum");
  std::string truncated = framed("M 17 9000 4200 350 120");
  EXPECT_EQ(parse_line(truncated.substr(0, 10), Dialect::Scanbus).kind, LineKind::Invalid);
  EXPECT_EQ(parse_line(framed("M 17 9000 4200"), Dialect::Scanbus).kind, LineKind::Invalid);
  EXPECT_EQ(parse_line(framed("M 17 9000 99000 350 1"), Dialect::Scanbus).text, "pitch beyond 180 degrees");
  EXPECT_EQ(parse_line(framed("M -1 9000 4200 350 1"), Dialect::Scanbus).kind, LineKind::Invalid);
  EXPECT_EQ(parse_line(framed("Q 1"), Dialect::Scanbus).text, "unknown tag");
  EXPECT_EQ(parse_line(std::string("\x01\xff\x80garbage*ZZ", 13), Dialect::Scanbus).kind, LineKind::Invalid);
  EXPECT_EQ(parse_line("", Dialect::Scanbus).kind, LineKind::Invalid);
}

TEST(DeviceProtocol, LegacyThesisLines) {
  const DeviceLine line = parse_line("1.57 3.14 250\r\n", Dialect::Legacy);
  ASSERT_EQ(line.kind, LineKind::Measurement);
  EXPECT_NEAR(line.measurement.pitch, 1.57, 1e-12);
  EXPECT_NEAR(line.measurement.yaw, 3.14, 1e-12);
  EXPECT_NEAR(line.measurement.range, 2.5, 1e-12);  // centimetres in, metres out
  EXPECT_EQ(parse_line("n", Dialect::Legacy).kind, LineKind::Lap);
  EXPECT_EQ(parse_line("d", Dialect::Legacy).kind, LineKind::Done);
  EXPECT_EQ(parse_line("1.57 nan 250", Dialect::Legacy).kind, LineKind::Invalid);
  EXPECT_EQ(parse_line("4.00 1.00 250", Dialect::Legacy).text, "pitch outside 0..pi");
  EXPECT_EQ(parse_line("1.57 1.00", Dialect::Legacy).kind, LineKind::Invalid);
}

TEST(ScanAssembler, RevolutionsScansAndGaps) {
  ScanAssembler assembler(RangeGate{0.05, 40});
  auto feed = feeder(assembler);
  feed("H scanbus-scanner 1 0.1.0");
  feed("M 0 0 9000 200 10");
  feed("M 1 100 9000 1 0");     // no return: out of range, kept in the batch, not a point
  feed("M 4 200 9000 200 10");  // 2 and 3 lost
  auto lap = feed("L 0 9000");
  ASSERT_TRUE(lap.revolution.has_value());
  EXPECT_EQ(lap.revolution->measurements.size(), 3u);
  EXPECT_EQ(lap.revolution->points.size(), 2u);
  EXPECT_EQ(lap.revolution->lost, 2u);
  EXPECT_NEAR(lap.revolution->points[0].position.x(), 2.0f, 1e-5f);
  feed("M 5 300 9300 300 10");
  feed("L 1 9300");
  const auto done = feed("D 0 2");
  ASSERT_TRUE(done.scan.has_value());
  EXPECT_EQ(done.scan->size(), 3u);
  EXPECT_EQ(done.scan_lost_lines, 2u);
  const ScanCounters& counters = assembler.counters();
  EXPECT_EQ(counters.lost_lines, 2u);
  EXPECT_EQ(counters.out_of_range, 1u);
  EXPECT_EQ(counters.revolutions, 2u);
  EXPECT_EQ(counters.scans, 1u);
}

TEST(ScanAssembler, EachScanCountsItsOwnLostLines) {
  ScanAssembler assembler(RangeGate{0.05, 40});
  auto feed = feeder(assembler);
  feed("M 5 0 9000 200 10");
  feed("M 8 100 9000 200 10");  // 6 and 7 lost
  feed("L 0 9000");
  EXPECT_EQ(feed("D 0 1").scan_lost_lines, 2u);
  feed("M 9 0 9000 200 10");
  feed("L 0 9000");
  const auto clean = feed("D 1 1");
  ASSERT_TRUE(clean.scan.has_value());
  EXPECT_EQ(clean.scan_lost_lines, 0u);
}

TEST(ScanAssembler, LinesLostRightAfterAConnectCountFromTheStatusLine) {
  ScanAssembler assembler(RangeGate{0.05, 40});
  auto feed = feeder(assembler);
  feed("S 1 1 199 0 7 0");    // a new reader: idle, 7 comes next
  feed("M 9 0 9000 200 10");  // 7 and 8 lost
  feed("L 0 9000");
  const auto done = feed("D 0 1");
  ASSERT_TRUE(done.scan.has_value());
  EXPECT_EQ(done.scan_lost_lines, 2u);
  feed("S 1 1 199 0 9 0");  // a status behind what came since: nothing lost
  feed("M 10 0 9000 200 10");
  EXPECT_EQ(assembler.counters().lost_lines, 2u);
}

TEST(ScanAssembler, AScanWhoseEndWasLostLeavesTheNextOneWhole) {
  ScanAssembler assembler(RangeGate{0.05, 40});
  auto feed = feeder(assembler);
  feed("M 0 0 9000 200 10");
  feed("L 0 9000");
  feed("M 1 0 9300 200 10");
  feed("L 1 9300");  // its 'D 0 2' never came
  feed("M 2 0 9000 200 10");
  feed("M 3 100 9000 200 10");
  feed("L 0 9000");  // a new scan's first revolution
  feed("M 4 0 9300 200 10");
  feed("L 1 9300");
  const auto done = feed("D 1 2");
  ASSERT_TRUE(done.scan.has_value());
  EXPECT_EQ(done.scan->size(), 3u);  // the new scan whole, the old one dropped
  EXPECT_EQ(assembler.counters().aborted_scans, 1u);
}

TEST(ScanAssembler, DeviceRestartAbortsThePartialScan) {
  ScanAssembler assembler(RangeGate{});
  auto feed = feeder(assembler);
  feed("M 0 0 9000 200 10");
  feed("L 0 9000");
  feed("H scanbus-scanner 1 0.1.0");  // power cycle: sequence starts over, no gap
  feed("M 0 0 9000 200 10");
  const auto done = feed("D 0 1");
  EXPECT_FALSE(done.scan.has_value());  // one lap seen, not the whole scan
  EXPECT_EQ(assembler.counters().lost_lines, 0u);
}

TEST(ScanAssembler, JoiningMidScanPublishesNoPartialScan) {
  ScanAssembler assembler(RangeGate{});
  auto feed = feeder(assembler);
  feed("M 40 0 9000 200 10");
  feed("L 5 5700");
  EXPECT_FALSE(feed("D 0 27").scan.has_value());
  feed("M 41 0 4200 200 10");
  feed("L 0 4200");
  EXPECT_TRUE(feed("D 1 1").scan.has_value());
  EXPECT_EQ(assembler.counters().aborted_scans, 1u);
  EXPECT_EQ(assembler.counters().scans, 1u);
}

TEST(ScanAssembler, BadLinesAreCountedNotFatal) {
  ScanAssembler assembler(RangeGate{});
  std::string corrupted = framed("M 0 0 9000 200 10");
  corrupted[2] = '7';
  assembler.add(parse_line(corrupted, Dialect::Scanbus), 0);
  assembler.add(parse_line("garbage", Dialect::Scanbus), 0);
  EXPECT_EQ(assembler.counters().checksum_errors, 1u);
  EXPECT_EQ(assembler.counters().malformed_lines, 1u);
}
