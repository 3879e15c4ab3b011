// Thin DDS node: a MAV log's records, in time order, as the sensors' messages. The stamps
// are the log's own, so a replay is repeatable and its output comparable with the truth.
#include "sensor_replay_node.hpp"

#include <cstdio>
#include <thread>

#include "mav_messages.hpp"
#include "scanbus/laser_scan_message.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/replay_pacer.hpp"

namespace scanbus::sensor_replay {

namespace {

struct Settings {
  std::string log;
  double rate;
  bool loop, truth;
  size_t wait_for_readers;
  double wait_timeout;
  double max_gap;  // s a stamp may jump from its neighbours' (ReplayPacer)
  double linger;   // s kept alive after the end, for readers behind (linger_for_lagging_readers)
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
  s.max_gap = config.number("max_gap", 60.0, 0.001, 1e6);
  s.linger = config.number("linger", 3.0, 0.0, 600.0);
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
        scans_(context.participant, topics::kScan),
        imus_(context.participant, topics::kImu),
        fixes_(context.participant, topics::kFix),
        pressures_(context.participant, topics::kPressure),
        truths_(context.participant, topics::kTruthPose) {}

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
    // Exiting deletes the writers, and with them what reliable readers have not acknowledged
    // yet: the flight's last scans on a loaded machine. (Best-effort readers acknowledge
    // nothing and cost no wait.)
    const auto acknowledged = [](auto& writer) { return writer.wait_for_acknowledgments(std::chrono::seconds(5)); };
    if (!(acknowledged(scans_) & acknowledged(imus_) & acknowledged(fixes_) & acknowledged(pressures_) &
          acknowledged(truths_)))
      log_->warn("readers did not acknowledge every sample within 5 s of the replay's end");
    linger_for_lagging_readers(settings_.linger);
    return 0;
  }

 private:
  // False when a stop was requested. A record whose stamp jumps more than max_gap from its
  // neighbours' is skipped, a pause in the log not waited for (ReplayPacer).
  bool replay(const std::vector<RecordRef>& records) {
    const auto started = std::chrono::steady_clock::now();
    ReplayPacer pacer(settings_.rate, settings_.max_gap);
    const RecordRef* held = nullptr;
    for (const RecordRef& record : records) {
      const auto step = pacer.next(record.stamp);
      if (step.skip_held) skipped(*held);
      if (step.publish_held) publish(*held);
      held = step.hold ? &record : nullptr;
      if (step.hold) continue;
      const auto due = started + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                     std::chrono::duration<double>(step.due));
      for (auto now = std::chrono::steady_clock::now(); now < due; now = std::chrono::steady_clock::now()) {
        const auto wait =
            std::chrono::duration_cast<std::chrono::milliseconds>(due - now) + std::chrono::milliseconds(1);
        if (StopSignal::wait_for(wait)) return false;
      }
      if (StopSignal::requested()) return false;
      publish(record);
    }
    if (pacer.finish()) skipped(*held);
    return true;
  }

  void skipped(const RecordRef& record) {
    ++health_.counter("stamps_skipped");
    health_.error("a record stamped " + std::to_string(record.stamp) + " s jumps more than max_gap (" +
                  std::to_string(settings_.max_gap) + " s) from its neighbours: skipped");
    log_->warn("{}: a record stamped {} s jumps more than {} s from its neighbours: skipped", settings_.log,
               record.stamp, settings_.max_gap);
  }

  void publish(const RecordRef& record) {
    switch (record.kind) {
      case RecordKind::Laser:
        scans_.write(to_laser_scan_message(data_.lasers[record.index], settings_.frames.laser));
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
