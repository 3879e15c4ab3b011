#include <gtest/gtest.h>

#include "scanbus/scanner_io/scanner_session.hpp"

using namespace scanbus::scanner_io;

namespace {

using Lines = std::vector<std::string>;

DeviceLine hello(int protocol = 1) {
  DeviceLine line;
  line.kind = LineKind::Hello;
  line.protocol_version = protocol;
  line.text = "0.1.0";
  return line;
}

DeviceLine status(uint8_t state) {
  DeviceLine line;
  line.kind = LineKind::Status;
  line.status.state = state;
  return line;
}

DeviceLine of_kind(LineKind kind) {
  DeviceLine line;
  line.kind = kind;
  return line;
}

SessionSettings settings(int scans, Dialect dialect = Dialect::Scanbus) {
  SessionSettings s;
  s.scans = scans;
  s.dialect = dialect;
  return s;
}

}  // namespace

TEST(ScannerSession, AsksADeviceThatBootedEarlierWhereItStandsAndStartsWhenIdle) {
  ScannerSession session(settings(1));
  EXPECT_EQ(session.state(), DeviceState::Disconnected);
  session.connected();
  EXPECT_EQ(session.take_to_device(), Lines({"STATUS"}));
  EXPECT_TRUE(session.expecting_lines()) << "the answer is due: silence is a stall";
  session.line(status(2), 0);  // already scanning (started before we connected): leave it
  EXPECT_EQ(session.state(), DeviceState::Scanning);
  EXPECT_TRUE(session.take_to_device().empty());
  session.line(status(0), 0);  // idle
  EXPECT_EQ(session.take_to_device(), Lines({"RES 1", "START"}));
}

TEST(ScannerSession, AHelloIsABootAndStartsTheConfiguredScansOnly) {
  ScannerSession session(settings(1));
  session.connected();
  session.take_to_device();
  session.line(hello(), 0);
  EXPECT_EQ(session.firmware(), "0.1.0");
  EXPECT_EQ(session.take_to_device(), Lines({"RES 1", "START"}));
  session.line(hello(), 0);  // rebooted: the START before is gone
  EXPECT_EQ(session.take_to_device(), Lines({"RES 1", "START"}));
  session.line(of_kind(LineKind::Measurement), 0);
  EXPECT_EQ(session.state(), DeviceState::Scanning);
  session.line(of_kind(LineKind::Done), 0);  // the one scan configured is done: no more
  EXPECT_EQ(session.state(), DeviceState::Idle);
  EXPECT_EQ(session.counters().scans, 1u);
  EXPECT_TRUE(session.take_to_device().empty());
  EXPECT_FALSE(session.expecting_lines());
  EXPECT_TRUE(session.take_problems().empty());
}

TEST(ScannerSession, KeepsScanningWhenToldTo) {
  ScannerSession session(settings(0));
  session.connected();
  session.line(hello(), 0);
  for (int scan = 0; scan < 3; ++scan) {
    EXPECT_EQ(session.take_to_device(), Lines(scan == 0 ? Lines{"STATUS", "RES 1", "START"} : Lines{"RES 1", "START"}));
    session.line(of_kind(LineKind::Done), 0);
  }
}

TEST(ScannerSession, NoAutostartSendsNothingButTheStatusQuestion) {
  SessionSettings s = settings(0);
  s.autostart = false;
  ScannerSession session(s);
  session.connected();
  session.line(hello(), 0);
  session.line(status(0), 0);
  EXPECT_EQ(session.take_to_device(), Lines({"STATUS"}));
  EXPECT_FALSE(session.expecting_lines()) << "an idle device may be silent for ever";
}

TEST(ScannerSession, ALostDeviceForgetsItsStartAndStartsAgainWhenBack) {
  ScannerSession session(settings(0));
  session.connected();
  session.line(hello(), 0);
  session.take_to_device();
  EXPECT_TRUE(session.expecting_lines());
  session.disconnected();
  EXPECT_EQ(session.state(), DeviceState::Disconnected);
  EXPECT_FALSE(session.expecting_lines());
  session.connected();
  session.line(status(0), 0);
  EXPECT_EQ(session.take_to_device(), Lines({"STATUS", "RES 1", "START"}));
}

TEST(ScannerSession, CommandsBecomeDeviceLinesAndBadOnesAreProblems) {
  ScannerSession session(settings(1));
  session.command({SessionCommand::SetResolution, 2});
  session.command({SessionCommand::Start});
  session.command({SessionCommand::Stop});
  session.command({SessionCommand::Status});
  EXPECT_EQ(session.take_to_device(), Lines({"RES 2", "RES 2", "START", "STOP", "STATUS"}));
  EXPECT_EQ(session.resolution(), 2);
  session.command({SessionCommand::SetResolution, 3});
  EXPECT_TRUE(session.take_to_device().empty());
  EXPECT_EQ(session.take_problems(), Lines({"resolution 3 does not exist (0, 1, 2)"}));
  session.line(hello(2), 0);
  EXPECT_EQ(session.take_problems(), Lines({"device speaks protocol 2, expected 1"}));
  DeviceLine error = of_kind(LineKind::DeviceError);
  error.text = "motor-stalled";
  session.line(error, 0);
  EXPECT_EQ(session.take_problems(), Lines({"device: motor-stalled"}));
}

TEST(ScannerSession, TheThesisFirmwareTakesNoCommands) {
  ScannerSession session(settings(1, Dialect::Legacy));
  session.connected();
  EXPECT_TRUE(session.take_to_device().empty()) << "the legacy firmware knows no STATUS";
  session.command({SessionCommand::Start});
  EXPECT_TRUE(session.take_to_device().empty());
  EXPECT_EQ(session.take_problems(), Lines({"commands are not supported with the legacy protocol"}));
}
