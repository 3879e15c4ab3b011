// Thin DDS node: serial lines in; SphericalScan and a PointCloud2 per revolution, the
// whole scan's cloud, and ScannerStatus out; ScannerCommand in, as device commands.
#include "scanner_io_node.hpp"

#include <cstdio>
#include <deque>
#include <filesystem>

#include "scanbus/clock.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/scanner_io/device_watchdog.hpp"
#include "scanbus/scanner_io/scan_assembler.hpp"
#include "serial_port.hpp"

namespace scanbus::scanner_io {

namespace {

namespace Status = scanbus::msg::ScannerStatus_Constants;
namespace Command = scanbus::msg::ScannerCommand_Constants;

struct Settings {
  std::string port;
  int baud;
  Dialect dialect;
  bool autostart;
  int resolution;
  int scans;
  double reconnect_min, reconnect_max;
  double stall_timeout;
  RangeGate gate;
  std::string frame_id;
};

Settings read_settings(const Config& config) {
  Settings s;
  s.port = config.text("port", "/dev/ttyACM0");
  s.baud = static_cast<int>(config.integer("baud", 115200, 1, 4000000));
  if (!supported_baud(s.baud))
    throw ConfigError(config.origin() + ": key '" + config.path_of("baud") + "' must be one of 9600, 19200, 38400, 57600, 115200, 230400");
  s.dialect = config.choice("protocol", "scanbus", {"scanbus", "legacy"}) == "scanbus" ? Dialect::Scanbus : Dialect::Legacy;
  s.autostart = config.flag("autostart", true);
  s.resolution = static_cast<int>(config.integer("resolution", 1, 0, 2));
  s.scans = static_cast<int>(config.integer("scans", 1, 0, 1000000));
  s.reconnect_min = config.number("reconnect_min", 0.2, 0.01, 60);
  s.reconnect_max = config.number("reconnect_max", 5.0, s.reconnect_min, 600);
  s.stall_timeout = config.number("stall_timeout", 5.0, 0.1, 3600);
  s.gate.min = config.number("min_range", 0.05, 0, 1000);
  s.gate.max = config.number("max_range", 40.0, s.gate.min, 1000);
  s.frame_id = config.text("frame_id", "scanner");
  return s;
}

class ScannerIo : public Service {
 public:
  explicit ScannerIo(ServiceContext& context)
      : log_(context.log),
        health_(context.health),
        settings_(read_settings(context.config.section("scanner_io"))),
        port_(settings_.port, settings_.baud),
        assembler_(settings_.gate),
        watchdog_(settings_.stall_timeout, settings_.reconnect_min, settings_.reconnect_max),
        spherical_(context.participant, "rt/scanner/spherical"),
        revolution_cloud_(context.participant, "rt/scanner/cloud"),
        scan_cloud_(context.participant, "rt/scanner/scan_cloud"),
        status_(context.participant, "rt/scanner/status"),
        commands_(context.participant, "rt/scanner/command", [this](const auto& command, const auto&) {
          std::lock_guard<std::mutex> lock(mutex_);
          pending_commands_.push_back(command);
        }) {}

  int run() override {
    double retry_delay = settings_.reconnect_min;
    auto next_status = std::chrono::steady_clock::now();
    while (!StopSignal::requested()) {
      if (!port_.is_open() && !connect(retry_delay)) continue;
      std::vector<std::string> lines;
      if (!port_.read_lines(lines, 100)) {
        disconnected("device closed the line");
        continue;
      }
      retry_delay = settings_.reconnect_min;
      for (const auto& line : lines) handle(parse_line(line, settings_.dialect));
      send_pending_commands();
      const double now = seconds_now();
      if (!lines.empty()) watchdog_.line(now);
      watchdog_.expect(state_ == Status::SCANNING || start_sent_ || status_asked_, now);
      if (watchdog_.stalled(now)) {
        stalled(now);
        continue;
      }
      if (std::chrono::steady_clock::now() >= next_status) {
        publish_status("");
        next_status = std::chrono::steady_clock::now() + std::chrono::seconds(1);
      }
    }
    return 0;
  }

 private:
  // Opens the port or waits the back-off; true when connected.
  bool connect(double& retry_delay) {
    std::string error;
    if (port_.open(error)) {
      log_->info("connected to {}", settings_.port);
      state_ = Status::IDLE;
      // A device that booted earlier said hello to no one: ask where it stands.
      if (settings_.dialect == Dialect::Scanbus) status_asked_ = port_.write_line("STATUS");
      publish_status("connected" + gap_text());
      return true;
    }
    if (error != last_error_) {
      log_->warn("{}; retrying with back-off up to {} s", error, settings_.reconnect_max);
      health_.error(error);
      last_error_ = error;
    }
    state_ = Status::DISCONNECTED;
    publish_status(error);
    wait_to_reconnect(retry_delay);
    retry_delay = std::min(retry_delay * 2, settings_.reconnect_max);
    return false;
  }

  // Waits the back-off before the next open. While the device node is missing (unplugged),
  // it is looked for every reconnect_min, so a replug is taken up at once, however long the
  // back-off has grown: the back-off spares a device that is there and fails to open.
  void wait_to_reconnect(double delay) {
    std::error_code error;
    const bool missing = !std::filesystem::exists(settings_.port, error);
    const double step = missing ? settings_.reconnect_min : delay;
    for (double waited = 0; waited < delay; waited += step) {
      if (StopSignal::wait_for(std::chrono::milliseconds(static_cast<int>(1000 * std::min(step, delay - waited))))) return;
      if (missing && std::filesystem::exists(settings_.port, error)) return;
    }
  }

  static double seconds_now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  }

  // No line while lines were due (DeviceWatchdog): the session is closed and, after the
  // back-off, opened again; the device is then asked where it stands and a scan started
  // as at any connection.
  void stalled(double now) {
    ++health_.counter("stalls");
    char why[128];
    std::snprintf(why, sizeof(why), "device stalled: no line for %.1f s while %s; resetting the session",
                  watchdog_.silent_for(now), state_ == Status::SCANNING ? "scanning" : "waiting for an answer");
    port_.close();
    disconnected(why);
    status_asked_ = false;
    StopSignal::wait_for(std::chrono::milliseconds(static_cast<int>(watchdog_.reset() * 1000)));
  }

  void disconnected(const std::string& why) {
    log_->warn("{}: {}; partial scan dropped", settings_.port, why);
    assembler_.abort();
    start_sent_ = false;
    lost_at_ = std::chrono::steady_clock::now();
    state_ = Status::DISCONNECTED;
    last_error_.clear();
    health_.error(settings_.port + ": " + why);
    publish_status(why);
  }

  std::string gap_text() const {
    if (!lost_at_) return "";
    char text[48];
    std::snprintf(text, sizeof(text), " after a gap of %.1f s",
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - *lost_at_).count());
    return text;
  }

  void handle(const DeviceLine& line) {
    const ScanOutput output = assembler_.add(line, std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count());
    switch (line.kind) {
      case LineKind::Hello:
        firmware_ = line.text;
        log_->info("device says hello: protocol {}, firmware {}", line.protocol_version, line.text);
        if (line.protocol_version != 1) health_.error("device speaks protocol " + std::to_string(line.protocol_version) + ", expected 1");
        start_sent_ = false;  // a boot: any START sent before is gone
        status_asked_ = false;
        maybe_start();
        break;
      case LineKind::Status:
        status_asked_ = false;
        device_status_ = line.status;
        state_ = line.status.state == 2 ? Status::SCANNING : Status::IDLE;
        if (state_ == Status::IDLE) maybe_start();
        break;
      case LineKind::DeviceError:
        log_->warn("device error {}: {}", line.error_code, line.text);
        health_.error("device: " + line.text);
        break;
      case LineKind::Measurement:
        state_ = Status::SCANNING;
        break;
      case LineKind::Done:
        state_ = Status::IDLE;
        start_sent_ = false;
        break;
      default:
        break;
    }
    if (output.revolution) publish_revolution(*output.revolution);
    if (output.scan) {
      scan_cloud_.write(to_point_cloud2(*output.scan, settings_.frame_id, now_stamp()));
      log_->info("scan complete: {} points", output.scan->size());
    }
    if (line.kind == LineKind::Done) maybe_start();
    update_counters();
  }

  // Starts the next scan when configured to and none is under way.
  void maybe_start() {
    const uint64_t completed = assembler_.counters().scans;
    if (settings_.autostart && !start_sent_ && (settings_.scans == 0 || completed < static_cast<uint64_t>(settings_.scans)))
      start_scan();
  }

  void start_scan() {
    start_sent_ = true;
    port_.write_line("RES " + std::to_string(settings_.resolution));
    port_.write_line("START");
  }

  void publish_revolution(const Revolution& revolution) {
    scanbus::msg::SphericalScan batch;
    batch.header().stamp(now_stamp());
    batch.header().frame_id(settings_.frame_id);
    batch.revolution(revolution.index);
    batch.lost(static_cast<uint32_t>(revolution.lost));
    batch.revolution_complete(true);
    for (const auto& m : revolution.measurements) {
      scanbus::msg::SphericalMeasurement out;
      out.stamp(to_stamp(m.stamp));
      out.line(m.line);
      out.yaw(static_cast<float>(m.yaw));
      out.pitch(static_cast<float>(m.pitch));
      out.range(static_cast<float>(m.range));
      out.signal(static_cast<float>(m.signal));
      batch.measurements().push_back(out);
    }
    if (!revolution.measurements.empty()) {
      batch.first_sequence(revolution.measurements.front().line);
      batch.last_sequence(revolution.measurements.back().line);
    }
    spherical_.write(batch);
    revolution_cloud_.write(to_point_cloud2(revolution.points, settings_.frame_id, batch.header().stamp()));
  }

  void send_pending_commands() {
    std::deque<scanbus::msg::ScannerCommand> commands;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      commands.swap(pending_commands_);
    }
    for (const auto& command : commands) {
      if (settings_.dialect == Dialect::Legacy) {
        health_.error("commands are not supported with the legacy protocol");
        continue;
      }
      switch (command.command()) {
        case Command::START: start_scan(); break;
        case Command::STOP: port_.write_line("STOP"); break;
        case Command::STATUS: port_.write_line("STATUS"); break;
        case Command::SET_RESOLUTION:
          if (command.resolution() > 2) {
            health_.error("resolution " + std::to_string(command.resolution()) + " does not exist (0, 1, 2)");
          } else {
            settings_.resolution = command.resolution();
            port_.write_line("RES " + std::to_string(settings_.resolution));
          }
          break;
        default: health_.error("unknown scanner command " + std::to_string(command.command()));
      }
    }
  }

  void update_counters() {
    const ScanCounters& c = assembler_.counters();
    health_.counter("lines") = c.lines;
    health_.counter("measurements") = c.measurements;
    health_.counter("lost_lines") = c.lost_lines;
    health_.counter("checksum_errors") = c.checksum_errors;
    health_.counter("malformed_lines") = c.malformed_lines + port_.overlong_lines();
    health_.counter("out_of_range") = c.out_of_range;
    health_.counter("revolutions") = c.revolutions;
    health_.counter("scans") = c.scans;
    health_.counter("aborted_scans") = c.aborted_scans;
  }

  void publish_status(const std::string& message) {
    const ScanCounters& c = assembler_.counters();
    scanbus::msg::ScannerStatus status;
    status.header().stamp(now_stamp());
    status.device(settings_.port);
    status.firmware(firmware_);
    status.state(state_);
    status.resolution(static_cast<uint8_t>(settings_.resolution));
    status.rpm(static_cast<float>(device_status_.rpm));
    status.revolutions(static_cast<uint32_t>(c.revolutions));
    status.measurements(c.measurements);
    status.lost_lines(c.lost_lines);
    status.checksum_errors(c.checksum_errors);
    status.malformed_lines(c.malformed_lines + port_.overlong_lines());
    status.out_of_range(c.out_of_range);
    status.aborted_scans(c.aborted_scans);
    status.message(message);
    status_.write(status);
  }

  std::shared_ptr<spdlog::logger> log_;
  HealthReporter& health_;
  Settings settings_;
  SerialPort port_;
  ScanAssembler assembler_;
  DeviceWatchdog watchdog_;
  Writer<scanbus::msg::SphericalScanPubSubType> spherical_;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> revolution_cloud_;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> scan_cloud_;
  Writer<scanbus::msg::ScannerStatusPubSubType> status_;
  std::mutex mutex_;
  std::deque<scanbus::msg::ScannerCommand> pending_commands_;
  Reader<scanbus::msg::ScannerCommandPubSubType> commands_;
  uint8_t state_ = Status::DISCONNECTED;
  DeviceStatus device_status_;
  std::string firmware_;
  std::string last_error_;
  bool start_sent_ = false;
  bool status_asked_ = false;  // STATUS sent on connecting, not answered yet
  std::optional<std::chrono::steady_clock::time_point> lost_at_;
};

}  // namespace

std::unique_ptr<Service> make_scanner_io(ServiceContext& context) { return std::make_unique<ScannerIo>(context); }

}  // namespace scanbus::scanner_io
