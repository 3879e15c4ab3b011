// The MAV's sensors as a text log, one sample per line (docs/mav_log.md): what
// `scanbus sim mav` writes, what the replay publishes, what the evaluations read. Units SI,
// stamps in s, positions in the map frame (ENU, origin on the ground at the start).
#pragma once

#include <Eigen/Geometry>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "scanbus/sensor/laser_scan.hpp"

namespace scanbus::sensor_replay {

class MavLogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ImuRecord {  // IMU: attitude of base_link in the map frame
  double stamp = 0;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

struct GpsRecord {  // GPS: WGS84 fix with its standard deviations
  double stamp = 0;
  double latitude = 0, longitude = 0, altitude = 0;  // deg, deg, m
  double horizontal_sigma = 0, vertical_sigma = 0;   // m
};

struct BaroRecord {  // BARO: static pressure
  double stamp = 0;
  double pressure = 0;  // Pa
};

struct TruthRecord {  // TRUTH: base_link in the map frame
  double stamp = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

struct MavLog {
  // META lines: `META name v1 v2 ...`. Known: origin (lat lon alt of the map origin),
  // laser_mount (x y z roll pitch yaw of the laser in base_link, rad), boxes (width length
  // height of each box on the ground, m), scenario (number).
  std::map<std::string, std::vector<double>> meta;
  std::vector<sensor::LaserScan> lasers;  // LASER: ROS LaserScan conventions (no return: +inf)
  std::vector<ImuRecord> imus;
  std::vector<GpsRecord> fixes;
  std::vector<BaroRecord> baros;
  std::vector<TruthRecord> truths;

  // The META entry, or throws MavLogError naming it.
  const std::vector<double>& meta_of(const std::string& name, size_t size) const;
};

// Every record of a log in time order (stable: equal stamps keep the order below), as a
// replay publishes them and the log file lists them.
enum class RecordKind { Laser, Imu, Gps, Baro, Truth };
struct RecordRef {
  double stamp;
  RecordKind kind;
  size_t index;  // into the vector of its kind
};
std::vector<RecordRef> records_in_time_order(const MavLog& log);

void write_mav_log(const std::string& path, const MavLog& log);
// Throws MavLogError naming the file and line of anything malformed.
MavLog read_mav_log(const std::string& path);

}  // namespace scanbus::sensor_replay
