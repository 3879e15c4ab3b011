#include "mav_messages.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "cdr.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/geometry_message.hpp"
#include "scanbus/laser_scan_message.hpp"
#include "scanbus/recorder/mcap_reader.hpp"
#include "scanbus/recorder/mcap_writer.hpp"
#include "scanbus/recorder/ros2msg.hpp"
#include "scanbus/typed_topics.hpp"
#include "scanbus_msgs/FluidPressurePubSubTypes.h"
#include "scanbus_msgs/ImuPubSubTypes.h"
#include "scanbus_msgs/LaserScanPubSubTypes.h"
#include "scanbus_msgs/NavSatFixPubSubTypes.h"
#include "scanbus_msgs/PoseStampedPubSubTypes.h"
#include "topic_channels.hpp"

namespace scanbus::sensor_replay {

namespace {

constexpr char kMetadataName[] = "scanbus_mav_log";

std_msgs::msg::Header header(double stamp, const std::string& frame) {
  std_msgs::msg::Header h;
  h.stamp(to_stamp(stamp));
  h.frame_id(frame);
  return h;
}

}  // namespace

sensor_msgs::msg::Imu imu_message(const ImuRecord& r, const std::string& frame) {
  sensor_msgs::msg::Imu imu;
  imu.header(header(r.stamp, frame));
  imu.orientation(to_quaternion_message(r.orientation));
  imu.angular_velocity_covariance()[0] = -1;  // not measured, as REP 145 says
  imu.linear_acceleration_covariance()[0] = -1;
  return imu;
}

sensor_msgs::msg::NavSatFix fix_message(const GpsRecord& r, const std::string& frame) {
  sensor_msgs::msg::NavSatFix fix;
  fix.header(header(r.stamp, frame));
  fix.status().status(sensor_msgs::msg::NavSatStatus_Constants::STATUS_FIX);
  fix.status().service(sensor_msgs::msg::NavSatStatus_Constants::SERVICE_GPS);
  fix.latitude(r.latitude);
  fix.longitude(r.longitude);
  fix.altitude(r.altitude);
  fix.position_covariance()[0] = fix.position_covariance()[4] = r.horizontal_sigma * r.horizontal_sigma;
  fix.position_covariance()[8] = r.vertical_sigma * r.vertical_sigma;
  fix.position_covariance_type(sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_DIAGONAL_KNOWN);
  return fix;
}

sensor_msgs::msg::FluidPressure pressure_message(const BaroRecord& r, const std::string& frame) {
  sensor_msgs::msg::FluidPressure pressure;
  pressure.header(header(r.stamp, frame));
  pressure.fluid_pressure(r.pressure);
  return pressure;
}

geometry_msgs::msg::PoseStamped truth_message(const TruthRecord& r, const std::string& frame) {
  geometry_msgs::msg::PoseStamped pose;
  pose.header(header(r.stamp, frame));
  pose.pose(to_pose_message(r.position, r.orientation));
  return pose;
}

void write_mav_mcap(const std::string& path, const MavLog& log, const MavFrames& frames) {
  using namespace recorder;
  McapWriter writer(path, {});
  std::map<std::string, std::string> meta;
  for (const auto& [name, values] : log.meta) {
    std::string text;
    char number[32];
    for (const double value : values) {
      std::snprintf(number, sizeof(number), "%.17g", value);
      text += (text.empty() ? "" : " ") + std::string(number);
    }
    meta[name] = text;
  }
  writer.add_metadata(kMetadataName, meta);
  TopicChannels topics(writer);
  std::map<RecordKind, uint16_t> channels;
  auto channel = [&](RecordKind kind, const std::string& topic) { channels[kind] = topics.add(topic); };
  channel(RecordKind::Laser, topics::kScan.name);
  channel(RecordKind::Imu, topics::kImu.name);
  channel(RecordKind::Gps, topics::kFix.name);
  channel(RecordKind::Baro, topics::kPressure.name);
  channel(RecordKind::Truth, topics::kTruthPose.name);
  std::map<RecordKind, uint32_t> sequence;
  for (const RecordRef& record : records_in_time_order(log)) {
    std::vector<uint8_t> bytes;
    switch (record.kind) {
      case RecordKind::Laser:
        bytes = to_cdr<sensor_msgs::msg::LaserScanPubSubType>(
            to_laser_scan_message(log.lasers[record.index], frames.laser));
        break;
      case RecordKind::Imu:
        bytes = to_cdr<sensor_msgs::msg::ImuPubSubType>(imu_message(log.imus[record.index], frames.base_link));
        break;
      case RecordKind::Gps:
        bytes = to_cdr<sensor_msgs::msg::NavSatFixPubSubType>(fix_message(log.fixes[record.index], frames.gps));
        break;
      case RecordKind::Baro:
        bytes = to_cdr<sensor_msgs::msg::FluidPressurePubSubType>(
            pressure_message(log.baros[record.index], frames.base_link));
        break;
      case RecordKind::Truth:
        bytes = to_cdr<geometry_msgs::msg::PoseStampedPubSubType>(truth_message(log.truths[record.index], frames.map));
        break;
    }
    const auto time = static_cast<uint64_t>(std::llround(record.stamp * 1e9));
    writer.write(channels[record.kind], sequence[record.kind]++, time, time, bytes.data(), bytes.size());
  }
  writer.close();
}

MavLog read_mav_mcap(const std::string& path) {
  using namespace recorder;
  MavLog log;
  try {
    McapReader reader(path);
    reader.read_messages([&](const McapMessage& m, const McapChannel& channel) {
      const std::string topic = dds_topic_of_ros_topic(channel.topic);
      if (topic == topics::kScan.name) {
        log.lasers.push_back(from_laser_scan_message(from_cdr<sensor_msgs::msg::LaserScanPubSubType>(m.data, m.size)));
      } else if (topic == topics::kImu.name) {
        const auto imu = from_cdr<sensor_msgs::msg::ImuPubSubType>(m.data, m.size);
        log.imus.push_back({to_seconds(imu.header().stamp()), to_eigen(imu.orientation())});
      } else if (topic == topics::kFix.name) {
        const auto fix = from_cdr<sensor_msgs::msg::NavSatFixPubSubType>(m.data, m.size);
        log.fixes.push_back({to_seconds(fix.header().stamp()), fix.latitude(), fix.longitude(), fix.altitude(),
                             std::sqrt(fix.position_covariance()[0]), std::sqrt(fix.position_covariance()[8])});
      } else if (topic == topics::kPressure.name) {
        const auto pressure = from_cdr<sensor_msgs::msg::FluidPressurePubSubType>(m.data, m.size);
        log.baros.push_back({to_seconds(pressure.header().stamp()), pressure.fluid_pressure()});
      } else if (topic == topics::kTruthPose.name) {
        const auto pose = from_cdr<geometry_msgs::msg::PoseStampedPubSubType>(m.data, m.size);
        log.truths.push_back(
            {to_seconds(pose.header().stamp()), to_eigen(pose.pose().position()), to_eigen(pose.pose().orientation())});
      }
    });
    const auto meta = reader.metadata().find(kMetadataName);
    if (meta == reader.metadata().end())
      throw MavLogError(path + ": no '" + kMetadataName + "' metadata (laser mount, origin): not a MAV recording");
    for (const auto& [name, text] : meta->second) {
      std::istringstream values(text);
      for (double value; values >> value;) log.meta[name].push_back(value);
    }
  } catch (const MavLogError&) {
    throw;
  } catch (const McapError& error) {  // names the file already
    throw MavLogError(error.what());
  } catch (const std::runtime_error& error) {  // bytes that do not decode
    throw MavLogError(path + ": " + error.what());
  }
  if (log.lasers.empty()) throw MavLogError(path + ": no LaserScan messages on /scan");
  return log;
}

MavLog load_mav_log(const std::string& path) {
  return recorder::is_mcap_path(path) ? read_mav_mcap(path) : read_mav_log(path);
}

void save_mav_log(const std::string& path, const MavLog& log) {
  if (recorder::is_mcap_path(path)) {
    write_mav_mcap(path, log);
  } else {
    write_mav_log(path, log);
  }
}

}  // namespace scanbus::sensor_replay
