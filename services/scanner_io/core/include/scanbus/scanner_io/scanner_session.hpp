// One device session's logic, without a port or DDS (the node reads the port, calls, writes):
// what to send the device when it connects, speaks or is commanded; when the next scan
// starts (`autostart`, `scans`); where the device stands. Lines for the device collect until
// take_to_device(), problems worth reporting until take_problems().
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "scanbus/scanner_io/device_protocol.hpp"
#include "scanbus/scanner_io/scan_assembler.hpp"

namespace scanbus::scanner_io {

struct SessionSettings {
  Dialect dialect = Dialect::Scanbus;
  bool autostart = true;  // on hello or an idle status: set the resolution and START a scan
  int resolution = 1;     // Table 4.2: 0 = 12 RPM, 1 = 20 RPM, 2 = 28 RPM
  int scans = 1;          // scans to start in a row (0 = keep scanning)
  RangeGate gate;         // returns outside it are not put in clouds
};

enum class DeviceState { Disconnected, Idle, Scanning };

struct SessionCommand {
  enum Kind { Start, Stop, Status, SetResolution } kind = Status;
  int resolution = 0;  // SetResolution's
};

class ScannerSession {
 public:
  explicit ScannerSession(const SessionSettings& settings);

  // The port opened. A device that booted earlier said hello to no one: it is asked where
  // it stands (scanbus dialect), and its answer starts a scan as a hello would.
  void connected();
  // The port closed, or the device went silent: the partial scan is dropped (only whole
  // scans are published) and any START sent is forgotten.
  void disconnected();
  // One line from the device, stamped `stamp` (s); what it completed.
  ScanOutput line(const DeviceLine& line, double stamp);
  void command(const SessionCommand& command);

  std::vector<std::string> take_to_device();
  std::vector<std::string> take_problems();

  DeviceState state() const { return state_; }
  // A measurement or an answer is due: silence then is a stall (DeviceWatchdog).
  bool expecting_lines() const { return state_ == DeviceState::Scanning || start_sent_ || status_asked_; }
  const std::string& firmware() const { return firmware_; }
  const DeviceStatus& device_status() const { return device_status_; }
  int resolution() const { return settings_.resolution; }
  const ScanCounters& counters() const { return assembler_.counters(); }

 private:
  void maybe_start();
  void start_scan();

  SessionSettings settings_;
  ScanAssembler assembler_;
  DeviceState state_ = DeviceState::Disconnected;
  DeviceStatus device_status_;
  std::string firmware_;
  bool start_sent_ = false;
  bool status_asked_ = false;  // STATUS sent on connecting, not answered yet
  std::vector<std::string> to_device_, problems_;
};

}  // namespace scanbus::scanner_io
