// Thin DDS node: serial lines in; SphericalScan and a PointCloud2 per revolution, the
// whole scan's cloud, and ScannerStatus out; ScannerCommand in, as device commands. The
// session's logic is ScannerSession's; here are the port, its back-off and watchdog timing,
// and the bus.
#include "scanner_io_node.hpp"

#include <cstdio>
#include <deque>
#include <filesystem>

#include "scanbus/clock.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/scanner_io/device_watchdog.hpp"
#include "scanbus/scanner_io/scanner_session.hpp"
#include "serial_port.hpp"

namespace scanbus::scanner_io {

namespace {

namespace Status = scanbus::msg::ScannerStatus_Constants;
namespace Command = scanbus::msg::ScannerCommand_Constants;

struct Settings {
  std::string port;
  int baud;
  SessionSettings session;
  double reconnect_min, reconnect_max;
  double stall_timeout;
  std::string frame_id;
};

uint8_t status_state(DeviceState state) {
  switch (state) {
    case DeviceState::Idle:
      return Status::IDLE;
    case DeviceState::Scanning:
      return Status::SCANNING;
    default:
      return Status::DISCONNECTED;
  }
}

Settings read_settings(const Config& config) {
  Settings s;
  s.port = config.text("port", "/dev/ttyACM0");
  s.baud = static_cast<int>(config.integer("baud", 115200, 1, 4000000));
  if (!supported_baud(s.baud))
    throw ConfigError(config.origin() + ": key '" + config.path_of("baud") +
                      "' must be one of 9600, 19200, 38400, 57600, 115200, 230400");
  s.session.dialect =
      config.choice("protocol", "scanbus", {"scanbus", "legacy"}) == "scanbus" ? Dialect::Scanbus : Dialect::Legacy;
  s.session.autostart = config.flag("autostart", true);
  s.session.resolution = static_cast<int>(config.integer("resolution", 1, 0, 2));
  s.session.scans = static_cast<int>(config.integer("scans", 1, 0, 1000000));
  s.reconnect_min = config.number("reconnect_min", 0.2, 0.01, 60);
  s.reconnect_max = config.number("reconnect_max", 5.0, s.reconnect_min, 600);
  s.stall_timeout = config.number("stall_timeout", 5.0, 0.1, 3600);
  s.session.gate.min = config.number("min_range", 0.05, 0, 1000);
  s.session.gate.max = config.number("max_range", 40.0, s.session.gate.min, 1000);
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
        session_(settings_.session),
        watchdog_(settings_.stall_timeout, settings_.reconnect_min, settings_.reconnect_max),
        spherical_(context.participant, topics::kScannerSpherical),
        revolution_cloud_(context.participant, topics::kScannerCloud),
        scan_cloud_(context.participant, topics::kScannerScanCloud),
        status_(context.participant, topics::kScannerStatus),
        commands_(context.participant, topics::kScannerCommand, [this](const auto& command, const auto&) {
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
      for (const auto& line : lines) handle(parse_line(line, settings_.session.dialect));
      send_pending_commands();
      const double now = steady_seconds();
      if (!lines.empty()) watchdog_.line(now);
      watchdog_.expect(session_.expecting_lines(), now);
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
      session_.connected();
      send_to_device();
      publish_status("connected" + gap_text());
      return true;
    }
    if (error != last_error_) {
      log_->warn("{}; retrying with back-off up to {} s", error, settings_.reconnect_max);
      health_.error(error);
      last_error_ = error;
    }
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
      if (StopSignal::wait_for(std::chrono::milliseconds(static_cast<int>(1000 * std::min(step, delay - waited)))))
        return;
      if (missing && std::filesystem::exists(settings_.port, error)) return;
    }
  }

  // No line while lines were due (DeviceWatchdog): the session is closed and, after the
  // back-off, opened again; the device is then asked where it stands and a scan started
  // as at any connection.
  void stalled(double now) {
    ++health_.counter("stalls");
    char why[128];
    std::snprintf(why, sizeof(why), "device stalled: no line for %.1f s while %s; resetting the session",
                  watchdog_.silent_for(now),
                  session_.state() == DeviceState::Scanning ? "scanning" : "waiting for an answer");
    port_.close();
    disconnected(why);
    StopSignal::wait_for(std::chrono::milliseconds(static_cast<int>(watchdog_.reset() * 1000)));
  }

  void disconnected(const std::string& why) {
    log_->warn("{}: {}; partial scan dropped", settings_.port, why);
    session_.disconnected();
    lost_at_ = std::chrono::steady_clock::now();
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
    const double stamp = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    const ScanOutput output = session_.line(line, stamp);
    if (line.kind == LineKind::Hello)
      log_->info("device says hello: protocol {}, firmware {}", line.protocol_version, line.text);
    if (output.revolution) publish_revolution(*output.revolution);
    if (output.scan) {
      scan_cloud_.write(to_point_cloud2(*output.scan, settings_.frame_id, now_stamp()));
      if (output.scan_lost_lines == 0)
        log_->info("scan complete: {} points", output.scan->size());
      else
        log_->warn("scan complete: {} points, {} lines lost on the link: the cloud has gaps", output.scan->size(),
                   output.scan_lost_lines);
      health_.recovered();  // a whole scan: the device (missing, unplugged, stalled) works again
    }
    send_to_device();
    update_counters();
  }

  // What the session has for the device, and what went wrong.
  void send_to_device() {
    for (const auto& line : session_.take_to_device()) port_.write_line(line);
    for (const auto& problem : session_.take_problems()) {
      log_->warn("{}", problem);
      health_.error(problem);
    }
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
      switch (command.command()) {
        case Command::START:
          session_.command({SessionCommand::Start});
          break;
        case Command::STOP:
          session_.command({SessionCommand::Stop});
          break;
        case Command::STATUS:
          session_.command({SessionCommand::Status});
          break;
        case Command::SET_RESOLUTION:
          session_.command({SessionCommand::SetResolution, command.resolution()});
          break;
        default:
          health_.error("unknown scanner command " + std::to_string(command.command()));
      }
    }
    send_to_device();
  }

  void update_counters() {
    const ScanCounters& c = session_.counters();
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
    const ScanCounters& c = session_.counters();
    scanbus::msg::ScannerStatus status;
    status.header().stamp(now_stamp());
    status.device(settings_.port);
    status.firmware(session_.firmware());
    status.state(status_state(session_.state()));
    status.resolution(static_cast<uint8_t>(session_.resolution()));
    status.rpm(static_cast<float>(session_.device_status().rpm));
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
  ScannerSession session_;
  DeviceWatchdog watchdog_;
  Writer<scanbus::msg::SphericalScanPubSubType> spherical_;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> revolution_cloud_;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> scan_cloud_;
  Writer<scanbus::msg::ScannerStatusPubSubType> status_;
  std::mutex mutex_;
  std::deque<scanbus::msg::ScannerCommand> pending_commands_;
  Reader<scanbus::msg::ScannerCommandPubSubType> commands_;
  std::string last_error_;
  std::optional<std::chrono::steady_clock::time_point> lost_at_;
};

}  // namespace

std::unique_ptr<Service> make_scanner_io(ServiceContext& context) { return std::make_unique<ScannerIo>(context); }

}  // namespace scanbus::scanner_io
