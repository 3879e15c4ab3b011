#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "scanbus/sim/simulated_hardware.hpp"
#include "scanner_core.h"

using namespace scanner;
using scanbus::sim::HardwareSettings;
using scanbus::sim::SimulatedHardware;

namespace {

struct Line {
  char tag;
  std::vector<std::string> fields;
  long number(size_t i) const { return std::stol(fields.at(i)); }
};

// Splits the device's output into lines, checking each line's checksum.
std::vector<Line> parse(const std::string& output) {
  std::vector<Line> lines;
  std::istringstream stream(output);
  std::string text;
  while (std::getline(stream, text)) {
    const size_t star = text.rfind('*');
    EXPECT_NE(star, std::string::npos) << text;
    if (star == std::string::npos) continue;
    char expected[3];
    std::snprintf(expected, sizeof(expected), "%02X", checksum(text.data(), static_cast<int>(star)));
    EXPECT_EQ(text.substr(star + 1), expected) << text;
    std::istringstream words(text.substr(0, star));
    Line line{text[0], {}};
    std::string word;
    words >> word;
    while (words >> word) line.fields.push_back(word);
    lines.push_back(line);
  }
  return lines;
}

struct Rig {
  explicit Rig(
      SimulatedHardware::RangeFunction range = [](const Eigen::Vector3d&, const Eigen::Vector3d&) { return 3.0; },
      HardwareSettings settings = quiet())
      : hardware(std::move(range), settings), core(hardware) {
    core.begin();
  }
  static HardwareSettings quiet() {
    HardwareSettings settings;
    settings.range_noise = 0;
    settings.dropout = 0;
    return settings;
  }
  std::vector<Line> send(const std::string& command) {
    hardware.feed_input(command);
    core.poll();
    return parse(hardware.take_output());
  }
  // Runs until the device says `tag` (or the time limit), returning everything it said.
  std::vector<Line> run_until(char tag, double limit_s) {
    std::vector<Line> all;
    const double end = hardware.time() + limit_s;
    while (hardware.time() < end) {
      core.poll();
      hardware.advance(0.0005);
      for (auto& line : parse(hardware.take_output())) {
        all.push_back(line);
        if (line.tag == tag) return all;
      }
    }
    return all;
  }
  SimulatedHardware hardware;
  ScannerCore core;
};

std::vector<Line> only(const std::vector<Line>& lines, char tag) {
  std::vector<Line> out;
  for (const auto& line : lines)
    if (line.tag == tag) out.push_back(line);
  return out;
}

}  // namespace

TEST(GearTrain, YawPerCountIsExact) {
  EXPECT_EQ(yaw_centidegrees(0), 0u);
  EXPECT_EQ(yaw_centidegrees(1), 83u);         // 0.8397 degrees, truncated
  EXPECT_EQ(yaw_centidegrees(343), 28800u);    // 343 counts are exactly 288 degrees
  EXPECT_EQ(yaw_centidegrees(1715), 144000u);  // four revolutions: 4 x 428.75 counts
  EXPECT_NEAR(yaw_centidegrees(1000000) / 1e6, 360.0 / (42.875 * 3) * 15 / 50 * 100, 1e-4);
  EXPECT_EQ(yaw_centidegrees(50000000u), 50000000ULL * 28800 / 343);  // no 32-bit overflow
}

TEST(GearTrain, InterpolationBetweenEdges) {
  // 28 RPM: 50 counts per 250 ms, so 2.5 ms after an edge is half a count.
  EXPECT_NEAR(yaw_since_edge_centidegrees(2500, 50), 42.0, 1.0);
  EXPECT_EQ(yaw_since_edge_centidegrees(0, 50), 0u);
  EXPECT_LT(yaw_since_edge_centidegrees(60000, 50), 84u);   // never past the next count
  EXPECT_EQ(yaw_since_edge_centidegrees(2000000, 50), 0u);  // stalled
}

TEST(Schedule, PitchAndSpeedsFromTheThesis) {
  EXPECT_EQ(pitch_degrees(0, 0), 42);
  EXPECT_EQ(pitch_degrees(26, 0), 120);
  EXPECT_EQ(pitch_degrees(0, 1), 43);  // eq. 4.9: the next cycle starts a degree later
  EXPECT_EQ(pitch_degrees(26, 2), 122);
  EXPECT_EQ(pitch_degrees(0, 3), 42);
  EXPECT_EQ(rpm_of_resolution(0), 12);
  EXPECT_EQ(rpm_of_resolution(1), 20);
  EXPECT_EQ(rpm_of_resolution(2), 28);
}

TEST(Protocol, FramingAndChecksum) {
  char line[kMaxLine];
  const uint32_t fields[] = {7, 123456, 4200, 350, 200};
  format_fields(line, 'M', fields, 5);
  EXPECT_EQ(std::string(line).rfind("M 7 123456 4200 350 200*", 0), 0u);
  const auto parsed = parse(line);
  ASSERT_EQ(parsed.size(), 1u);
  EXPECT_EQ(parsed[0].number(1), 123456);
  EXPECT_EQ(checksum("AB", 2), 'A' ^ 'B');
}

TEST(Commands, HelloStatusAndErrors) {
  SimulatedHardware hardware([](const Eigen::Vector3d&, const Eigen::Vector3d&) { return 3.0; }, Rig::quiet());
  ScannerCore core(hardware);
  core.begin();
  const auto hello = parse(hardware.take_output());
  ASSERT_EQ(hello.size(), 1u);
  EXPECT_EQ(hello[0].tag, 'H');
  EXPECT_EQ(hello[0].fields[0], "scanbus-scanner");
  EXPECT_EQ(hello[0].fields[1], "1");

  Rig rig;
  rig.hardware.take_output();
  auto reply = rig.send("JUMP\n");
  ASSERT_EQ(reply.size(), 1u);
  EXPECT_EQ(reply[0].tag, 'E');
  EXPECT_EQ(reply[0].fields[0], "1");
  EXPECT_EQ(reply[0].fields[1], "unknown-command");
  EXPECT_EQ(rig.send("RES 7\n")[0].fields[1], "bad-argument");
  reply = rig.send("RES 2\r\n");
  ASSERT_EQ(reply[0].tag, 'S');
  EXPECT_EQ(reply[0].number(1), 2);
  EXPECT_EQ(rig.send(std::string(40, 'X') + "\n")[0].fields[1], "line-too-long");
  reply = rig.send("STATUS\n");
  EXPECT_EQ(reply[0].number(0), kIdle);
  rig.send("START\n");
  EXPECT_EQ(rig.core.state(), kScanning);
  EXPECT_EQ(rig.send("START\n")[0].fields[1], "busy");
  EXPECT_EQ(rig.send("RES 1\n")[0].fields[1], "busy");
  reply = rig.send("STOP\n");
  EXPECT_EQ(reply[0].number(0), kIdle);
  EXPECT_EQ(rig.core.motor_duty(), 0);
}

TEST(Scan, FullScanAtTwelveRpm) {
  Rig rig;
  rig.send("RES 0\n");
  rig.send("START\n");
  const auto lines = rig.run_until('D', 200.0);
  const auto laps = only(lines, 'L');
  const auto measurements = only(lines, 'M');
  ASSERT_EQ(laps.size(), 27u);
  for (size_t i = 0; i < laps.size(); ++i) {
    EXPECT_EQ(laps[i].number(0), static_cast<long>(i));
    EXPECT_EQ(laps[i].number(1), 4200 + 300 * static_cast<long>(i));
  }
  ASSERT_EQ(only(lines, 'D').size(), 1u);
  EXPECT_EQ(rig.core.state(), kIdle);
  EXPECT_EQ(rig.core.motor_duty(), 0);
  // 5 s per revolution at 12 RPM and 50 Hz: about 250 a revolution (Table 4.2), less the
  // servo's settling after each pitch step and the motor's spin-up.
  EXPECT_GT(measurements.size(), 27u * 235);
  EXPECT_LE(measurements.size(), 27u * 251);
  for (size_t i = 0; i < measurements.size(); ++i) EXPECT_EQ(measurements[i].number(0), static_cast<long>(i));
  // Yaw only grows, across revolutions too, and ends past 27 turns.
  for (size_t i = 1; i < measurements.size(); ++i) EXPECT_GT(measurements[i].number(1), measurements[i - 1].number(1));
  EXPECT_GT(measurements.back().number(1), 27 * 36000 - 200);
  EXPECT_EQ(measurements.front().number(3), 300);  // 3 m in cm
}

TEST(Scan, SpeedControlHoldsEachSetting) {
  for (uint8_t resolution = 0; resolution < kResolutions; ++resolution) {
    Rig rig;
    rig.send("RES " + std::to_string(resolution) + "\n");
    rig.send("START\n");
    rig.run_until('?', 4.0);
    const auto status = only(rig.send("STATUS\n"), 'S');
    ASSERT_EQ(status.size(), 1u);
    EXPECT_NEAR(status.back().number(2) / 10.0, rpm_of_resolution(resolution), 0.06 * rpm_of_resolution(resolution))
        << "resolution " << int(resolution);
  }
}

TEST(Scan, ReportedYawMatchesThePole) {
  std::vector<double> true_yaw;
  Rig rig([&](const Eigen::Vector3d&, const Eigen::Vector3d& direction) {
    true_yaw.push_back(std::atan2(direction.y(), direction.x()));
    return 3.0;
  });
  rig.send("RES 2\n");
  rig.send("START\n");
  const auto measurements = only(rig.run_until('L', 10.0), 'M');
  ASSERT_EQ(measurements.size(), true_yaw.size());
  ASSERT_GT(measurements.size(), 50u);
  // Interpolating from the last encoder edge keeps the error far below one count (0.84
  // degrees; reporting the count alone would average half of that).
  double sum = 0;
  for (size_t i = 0; i < measurements.size(); ++i) {
    const double reported = measurements[i].number(1) / 100.0 * M_PI / 180.0;
    const double error = std::abs(std::remainder(reported - true_yaw[i], 2 * M_PI)) * 180 / M_PI;
    EXPECT_LT(error, 0.15) << "measurement " << i;
    sum += error;
  }
  EXPECT_LT(sum / measurements.size(), 0.05);
}

TEST(Scan, NextCycleShiftsThePitch) {
  Rig rig;
  rig.send("RES 2\n");
  rig.send("START\n");
  rig.run_until('D', 120.0);
  rig.send("START\n");
  const auto first_lap = only(rig.run_until('L', 10.0), 'L');
  ASSERT_EQ(first_lap.size(), 1u);
  EXPECT_EQ(first_lap[0].number(1), 4300);
  EXPECT_EQ(rig.core.cycle(), 1);
}
