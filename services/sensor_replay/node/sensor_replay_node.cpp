// Thin DDS node: a MAV log's records, in time order, as the sensors' messages. The stamps
// are the log's own, so a replay is repeatable and its output comparable with the truth.
#include "sensor_replay_node.hpp"

#include <cstdio>
#include <thread>

#include "scanbus/messages.hpp"
#include "mav_messages.hpp"

namespace scanbus::sensor_replay {

namespace {

struct Settings {
  std::string log;
  double rate;
  bool loop, truth;
  size_t wait_for_readers;
  double wait_timeout;
  MavFrames frames;
};

Settings read_settings(const Config& config) {
  Settings s;
  s.log = config.text("log", "");
  if (s.log.empty()) config.fail("log", "must name the MAV log to replay");
  s.rate = config.number("rate", 1.0, 0.0, 1000.0);
  s.loop = config.flag("loop", false);
  s.truth = config.flag("truth", true);
  s.wait_for_readers = static_cast<size_t>(config.integer("wait_for_readers", 0, 0, 100));
  s.wait_timeout = config.number("wait_timeout", 10.0, 0.0, 3600.0);
  const Config frames = config.section("frames");
  s.frames.laser = frames.text("laser", s.frames.laser);
  s.frames.base_link = frames.text("base_link", s.frames.base_link);
  s.frames.gps = frames.text("gps", s.frames.gps);
  s.frames.map = frames.text("map", s.frames.map);
  return s;
}

class SensorReplay : public Service {
 public:
  explicit SensorReplay(ServiceContext& context)
      : log_(context.log),
        health_(context.health),
        settings_(read_settings(context.config.section("sensor_replay"))),
        scans_(context.participant, "rt/scan"),
        imus_(context.participant, "rt/imu"),
        fixes_(context.participant, "rt/fix"),
        pressures_(context.participant, "rt/pressure"),
        truths_(context.participant, "rt/truth/pose") {}

  int run() override {
    try {
      data_ = load_mav_log(settings_.log);
    } catch (const MavLogError& e) {
      log_->error("{}", e.what());
      std::fprintf(stderr, "sensor_replay: %s\n", e.what());
      return 2;
    }
    if (settings_.wait_for_readers > 0 &&
        !scans_.wait_for_readers(settings_.wait_for_readers,
                                 std::chrono::milliseconds(static_cast<long>(settings_.wait_timeout * 1000)))) {
      log_->warn("only {} of {} rt/scan readers after {} s; replaying anyway", scans_.matched_readers(),
                 settings_.wait_for_readers, settings_.wait_timeout);
    }
    const auto records = records_in_time_order(data_);
    do {
      if (!replay(records)) return 0;
      ++health_.counter("replays");
    } while (settings_.loop);
    log_->info("replay of {} done: {} records", settings_.log, records.size());
    truths_.wait_for_acknowledgments(std::chrono::seconds(2));
    return 0;
  }

 private:
  // False when a stop was requested.
  bool replay(const std::vector<RecordRef>& records) {
    if (records.empty()) return true;
    const auto started = std::chrono::steady_clock::now();
    const double first = records.front().stamp;
    for (const RecordRef& record : records) {
      if (settings_.rate > 0) {
        const auto due = started + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                       std::chrono::duration<double>((record.stamp - first) / settings_.rate));
        for (auto now = std::chrono::steady_clock::now(); now < due; now = std::chrono::steady_clock::now()) {
          const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(due - now) + std::chrono::milliseconds(1);
          if (StopSignal::wait_for(wait)) return false;
        }
      } else if (StopSignal::requested()) {
        return false;
      }
      publish(record);
    }
    return true;
  }

  void publish(const RecordRef& record) {
    switch (record.kind) {
      case RecordKind::Laser:
        scans_.write(laser_message(data_.lasers[record.index], settings_.frames.laser));
        ++health_.counter("scans");
        break;
      case RecordKind::Imu:
        imus_.write(imu_message(data_.imus[record.index], settings_.frames.base_link));
        ++health_.counter("imu");
        break;
      case RecordKind::Gps:
        fixes_.write(fix_message(data_.fixes[record.index], settings_.frames.gps));
        ++health_.counter("fixes");
        break;
      case RecordKind::Baro:
        pressures_.write(pressure_message(data_.baros[record.index], settings_.frames.base_link));
        ++health_.counter("pressures");
        break;
      case RecordKind::Truth:
        if (settings_.truth) truths_.write(truth_message(data_.truths[record.index], settings_.frames.map));
        break;
    }
  }

  std::shared_ptr<spdlog::logger> log_;
  HealthReporter& health_;
  Settings settings_;
  MavLog data_;
  Writer<sensor_msgs::msg::LaserScanPubSubType> scans_;
  Writer<sensor_msgs::msg::ImuPubSubType> imus_;
  Writer<sensor_msgs::msg::NavSatFixPubSubType> fixes_;
  Writer<sensor_msgs::msg::FluidPressurePubSubType> pressures_;
  Writer<geometry_msgs::msg::PoseStampedPubSubType> truths_;
};

}  // namespace

std::unique_ptr<Service> make_sensor_replay(ServiceContext& context) { return std::make_unique<SensorReplay>(context); }

}  // namespace scanbus::sensor_replay
