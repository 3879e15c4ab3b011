// Thin DDS node: measurements from the source go out as SphericalScan, a cloud per
// revolution, and the whole scan's cloud once every pitch step is done.
#include "scanner_io_node.hpp"

#include "scanbus/clock.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/scanner_io/spherical.hpp"
#include "scanbus/sim/simulated_scanner.hpp"

namespace scanbus::scanner_io {

namespace {

struct SimulatedSource {
  int resolution;
  double rate;
  double noise;
  int scans;
  unsigned seed;
};

class ScannerIo : public Service {
 public:
  explicit ScannerIo(ServiceContext& context)
      : log_(context.log),
        spherical_(context.participant, "rt/scanner/spherical"),
        revolution_cloud_(context.participant, "rt/scanner/cloud"),
        scan_cloud_(context.participant, "rt/scanner/scan_cloud"),
        status_(context.participant, "rt/scanner/status"),
        measurements_(context.health.counter("measurements")),
        dropped_(context.health.counter("dropped_by_range_gate")),
        revolutions_(context.health.counter("revolutions")) {
    const Config config = context.config.section("scanner_io");
    config.choice("source", "simulated", {"simulated"});
    gate_.min = config.number("min_range", gate_.min, 0.0, 1000.0);
    gate_.max = config.number("max_range", gate_.max, 0.0, 1000.0);
    if (gate_.max <= gate_.min) throw ConfigError(config.origin() + ": key '" + config.path_of("max_range") + "' must exceed min_range");
    frame_id_ = config.text("frame_id", "scanner");
    const Config simulated = config.section("simulated");
    source_.resolution = static_cast<int>(simulated.integer("resolution", 0, 0, 2));
    source_.rate = simulated.number("rate", 10.0, 0.0, 1000.0);
    source_.noise = simulated.number("noise", 0.02, 0.0, 1.0);
    source_.scans = static_cast<int>(simulated.integer("scans", 1, 0, 1000000));
    source_.seed = static_cast<unsigned>(simulated.integer("seed", 1, 0, 1u << 31));
  }

  int run() override {
    sim::ScanPattern pattern;
    pattern.rpm = sim::speed_setting(source_.resolution).rpm;
    sim::SimulatedScanner scanner(sim::RoomModel::built_in(), pattern, source_.noise, source_.seed);
    publish_status(scanbus::msg::ScannerStatus_Constants::SCANNING, pattern.rpm, "simulated scan running");
    for (int cycle = 0; source_.scans == 0 || cycle < source_.scans; ++cycle) {
      std::vector<CloudPoint> scan_points;
      for (int revolution = 0; revolution < pattern.pitch_steps; ++revolution) {
        const auto samples = scanner.revolution(revolution, cycle);
        publish_revolution(samples, revolution, scan_points);
        // Paced like the device (scaled by rate), so subscribers see a scan unfold.
        const double pause = source_.rate > 0 ? pattern.revolution_period() / source_.rate : 0.0;
        if (StopSignal::wait_for(std::chrono::milliseconds(static_cast<int>(1000 * pause)))) return 0;
      }
      scan_cloud_.write(to_point_cloud2(scan_points, frame_id_, now_stamp()));
      log_->info("scan {} complete: {} points", cycle, scan_points.size());
    }
    publish_status(scanbus::msg::ScannerStatus_Constants::IDLE, 0, "scans complete");
    while (!StopSignal::wait_for(std::chrono::milliseconds(500))) {
    }
    return 0;
  }

 private:
  void publish_revolution(const std::vector<sim::SimulatedSample>& samples, int revolution,
                          std::vector<CloudPoint>& scan_points) {
    scanbus::msg::SphericalScan batch;
    batch.header().stamp(now_stamp());
    batch.header().frame_id(frame_id_);
    batch.revolution(static_cast<uint32_t>(revolution));
    batch.first_sequence(line_);
    std::vector<CloudPoint> points;
    for (const auto& sample : samples) {
      const SphericalMeasurement measurement{sample.time, line_++, sample.yaw, sample.pitch, sample.range, sample.signal};
      scanbus::msg::SphericalMeasurement out;
      out.stamp(to_stamp(measurement.stamp));
      out.line(measurement.line);
      out.yaw(static_cast<float>(measurement.yaw));
      out.pitch(static_cast<float>(measurement.pitch));
      out.range(static_cast<float>(measurement.range));
      out.signal(static_cast<float>(measurement.signal));
      batch.measurements().push_back(out);
      if (in_gate(measurement, gate_)) {
        points.push_back({to_cartesian(measurement.range, measurement.yaw, measurement.pitch),
                          static_cast<float>(measurement.signal)});
      } else {
        ++dropped_;
      }
    }
    batch.last_sequence(line_ - 1);
    batch.revolution_complete(true);
    measurements_ += samples.size();
    ++revolutions_;
    spherical_.write(batch);
    revolution_cloud_.write(to_point_cloud2(points, frame_id_, batch.header().stamp()));
    scan_points.insert(scan_points.end(), points.begin(), points.end());
  }

  void publish_status(uint8_t state, double rpm, const std::string& message) {
    scanbus::msg::ScannerStatus status;
    status.header().stamp(now_stamp());
    status.device("simulated");
    status.state(state);
    status.resolution(static_cast<uint8_t>(source_.resolution));
    status.rpm(static_cast<float>(rpm));
    status.revolutions(static_cast<uint32_t>(revolutions_.load()));
    status.measurements(measurements_.load());
    status.message(message);
    status_.write(status);
  }

  std::shared_ptr<spdlog::logger> log_;
  Writer<scanbus::msg::SphericalScanPubSubType> spherical_;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> revolution_cloud_;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> scan_cloud_;
  Writer<scanbus::msg::ScannerStatusPubSubType> status_;
  std::atomic<uint64_t>& measurements_;
  std::atomic<uint64_t>& dropped_;
  std::atomic<uint64_t>& revolutions_;
  RangeGate gate_;
  std::string frame_id_;
  SimulatedSource source_{};
  uint32_t line_ = 0;
};

}  // namespace

std::unique_ptr<Service> make_scanner_io(ServiceContext& context) { return std::make_unique<ScannerIo>(context); }

}  // namespace scanbus::scanner_io
