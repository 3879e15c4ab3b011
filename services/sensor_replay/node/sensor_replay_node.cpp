// Thin DDS node: a MAV log's records, in time order, as the sensors' messages. The stamps
// are the log's own, so a replay is repeatable and its output comparable with the truth.
#include "sensor_replay_node.hpp"

#include <cmath>
#include <cstdio>
#include <thread>

#include "scanbus/clock.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/sensor_replay/mav_log.hpp"

namespace scanbus::sensor_replay {

namespace {

struct Settings {
  std::string log;
  double rate;
  bool loop, truth;
  size_t wait_for_readers;
  double wait_timeout;
  std::string laser_frame, body_frame, gps_frame, map_frame;
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
  s.laser_frame = frames.text("laser", "laser");
  s.body_frame = frames.text("base_link", "base_link");
  s.gps_frame = frames.text("gps", "gps");
  s.map_frame = frames.text("map", "map");
  return s;
}

std_msgs::msg::Header header(double stamp, const std::string& frame) {
  std_msgs::msg::Header h;
  h.stamp(to_stamp(stamp));
  h.frame_id(frame);
  return h;
}

geometry_msgs::msg::Quaternion quaternion(const Eigen::Quaterniond& q) {
  geometry_msgs::msg::Quaternion message;
  message.x(q.x());
  message.y(q.y());
  message.z(q.z());
  message.w(q.w());
  return message;
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
      data_ = read_mav_log(settings_.log);
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
      case RecordKind::Laser: {
        const auto& r = data_.lasers[record.index];
        sensor_msgs::msg::LaserScan scan;
        scan.header(header(r.stamp, settings_.laser_frame));
        scan.angle_min(static_cast<float>(r.angle_min));
        scan.angle_increment(static_cast<float>(r.angle_increment));
        scan.angle_max(static_cast<float>(r.angle_min + r.angle_increment * (r.ranges.size() - 1)));
        scan.range_min(static_cast<float>(r.range_min));
        scan.range_max(static_cast<float>(r.range_max));
        scan.ranges(r.ranges);
        scans_.write(scan);
        ++health_.counter("scans");
        break;
      }
      case RecordKind::Imu: {
        sensor_msgs::msg::Imu imu;
        imu.header(header(data_.imus[record.index].stamp, settings_.body_frame));
        imu.orientation(quaternion(data_.imus[record.index].orientation));
        imu.angular_velocity_covariance()[0] = -1;  // not measured, as REP 145 says
        imu.linear_acceleration_covariance()[0] = -1;
        imus_.write(imu);
        ++health_.counter("imu");
        break;
      }
      case RecordKind::Gps: {
        const auto& r = data_.fixes[record.index];
        sensor_msgs::msg::NavSatFix fix;
        fix.header(header(r.stamp, settings_.gps_frame));
        fix.status().status(sensor_msgs::msg::NavSatStatus_Constants::STATUS_FIX);
        fix.status().service(sensor_msgs::msg::NavSatStatus_Constants::SERVICE_GPS);
        fix.latitude(r.latitude);
        fix.longitude(r.longitude);
        fix.altitude(r.altitude);
        fix.position_covariance()[0] = fix.position_covariance()[4] = r.horizontal_sigma * r.horizontal_sigma;
        fix.position_covariance()[8] = r.vertical_sigma * r.vertical_sigma;
        fix.position_covariance_type(sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_DIAGONAL_KNOWN);
        fixes_.write(fix);
        ++health_.counter("fixes");
        break;
      }
      case RecordKind::Baro: {
        sensor_msgs::msg::FluidPressure pressure;
        pressure.header(header(data_.baros[record.index].stamp, settings_.body_frame));
        pressure.fluid_pressure(data_.baros[record.index].pressure);
        pressures_.write(pressure);
        ++health_.counter("pressures");
        break;
      }
      case RecordKind::Truth: {
        if (!settings_.truth) break;
        const auto& r = data_.truths[record.index];
        geometry_msgs::msg::PoseStamped pose;
        pose.header(header(r.stamp, settings_.map_frame));
        pose.pose().position().x(r.position.x());
        pose.pose().position().y(r.position.y());
        pose.pose().position().z(r.position.z());
        pose.pose().orientation(quaternion(r.orientation));
        truths_.write(pose);
        break;
      }
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
