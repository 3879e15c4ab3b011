#include "scanbus/scanner_io/scanner_session.hpp"

#include <utility>

namespace scanbus::scanner_io {

ScannerSession::ScannerSession(const SessionSettings& settings) : settings_(settings), assembler_(settings.gate) {}

void ScannerSession::connected() {
  state_ = DeviceState::Idle;
  if (settings_.dialect == Dialect::Scanbus) {
    to_device_.push_back("STATUS");
    status_asked_ = true;
  }
}

void ScannerSession::disconnected() {
  assembler_.abort();
  state_ = DeviceState::Disconnected;
  start_sent_ = false;
  status_asked_ = false;
}

ScanOutput ScannerSession::line(const DeviceLine& line, double stamp) {
  const ScanOutput output = assembler_.add(line, stamp);
  switch (line.kind) {
    case LineKind::Hello:
      firmware_ = line.text;
      if (line.protocol_version != 1)
        problems_.push_back("device speaks protocol " + std::to_string(line.protocol_version) + ", expected 1");
      start_sent_ = false;  // a boot: any START sent before is gone
      status_asked_ = false;
      maybe_start();
      break;
    case LineKind::Status:
      status_asked_ = false;
      device_status_ = line.status;
      state_ = line.status.state == 2 ? DeviceState::Scanning : DeviceState::Idle;
      if (state_ == DeviceState::Idle) maybe_start();
      break;
    case LineKind::DeviceError:
      problems_.push_back("device: " + line.text);
      break;
    case LineKind::Measurement:
      state_ = DeviceState::Scanning;
      break;
    case LineKind::Done:
      state_ = DeviceState::Idle;
      start_sent_ = false;
      maybe_start();
      break;
    default:
      break;
  }
  return output;
}

void ScannerSession::command(const SessionCommand& command) {
  if (settings_.dialect == Dialect::Legacy) {
    problems_.push_back("commands are not supported with the legacy protocol");
    return;
  }
  switch (command.kind) {
    case SessionCommand::Start:
      start_scan();
      break;
    case SessionCommand::Stop:
      to_device_.push_back("STOP");
      break;
    case SessionCommand::Status:
      to_device_.push_back("STATUS");
      break;
    case SessionCommand::SetResolution:
      if (command.resolution < 0 || command.resolution > 2) {
        problems_.push_back("resolution " + std::to_string(command.resolution) + " does not exist (0, 1, 2)");
      } else {
        settings_.resolution = command.resolution;
        to_device_.push_back("RES " + std::to_string(settings_.resolution));
      }
      break;
  }
}

std::vector<std::string> ScannerSession::take_to_device() { return std::exchange(to_device_, {}); }

std::vector<std::string> ScannerSession::take_problems() { return std::exchange(problems_, {}); }

void ScannerSession::maybe_start() {
  const uint64_t completed = assembler_.counters().scans;
  if (settings_.autostart && !start_sent_ &&
      (settings_.scans == 0 || completed < static_cast<uint64_t>(settings_.scans)))
    start_scan();
}

void ScannerSession::start_scan() {
  start_sent_ = true;
  to_device_.push_back("RES " + std::to_string(settings_.resolution));
  to_device_.push_back("START");
}

}  // namespace scanbus::scanner_io
