#include "scanbus/sensor_replay/mav_log.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace scanbus::sensor_replay {

namespace {

constexpr const char* kHeader = "# scanbus MAV log v1 (docs/mav_log.md)";

void write_quaternion(std::ostream& out, const Eigen::Quaterniond& q) {
  out << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w();
}

template <class... Values>
void read_values(std::istringstream& words, const std::string& where, Values&... values) {
  if (!((words >> values) && ...)) throw MavLogError(where + ": too few or malformed values");
}

Eigen::Quaterniond read_quaternion(std::istringstream& words, const std::string& where) {
  double x, y, z, w;
  read_values(words, where, x, y, z, w);
  const Eigen::Quaterniond q(w, x, y, z);
  if (!(std::abs(q.norm() - 1) < 1e-3)) throw MavLogError(where + ": quaternion is not a unit quaternion");
  return q.normalized();
}

sensor::LaserScan read_laser(std::istringstream& words, const std::string& where) {
  sensor::LaserScan laser;
  size_t count = 0;
  read_values(words, where, laser.stamp, laser.angle_min, laser.angle_increment, laser.range_min, laser.range_max,
              count);
  if (count == 0 || count > 100000) throw MavLogError(where + ": implausible ray count " + std::to_string(count));
  laser.ranges.resize(count);
  for (float& range : laser.ranges) {
    std::string word;
    if (!(words >> word)) throw MavLogError(where + ": expected " + std::to_string(count) + " ranges");
    try {
      range = word == "inf" ? INFINITY : std::stof(word);
    } catch (const std::exception&) {
      throw MavLogError(where + ": range '" + word + "' is not a number");
    }
  }
  return laser;
}

}  // namespace

const std::vector<double>& MavLog::meta_of(const std::string& name, size_t size) const {
  const auto found = meta.find(name);
  if (found == meta.end() || found->second.size() < size)
    throw MavLogError("the log has no META " + name + " line with " + std::to_string(size) + " values");
  return found->second;
}

std::vector<RecordRef> records_in_time_order(const MavLog& log) {
  std::vector<RecordRef> records;
  const auto add = [&](const auto& entries, RecordKind kind) {
    for (size_t i = 0; i < entries.size(); ++i) records.push_back({entries[i].stamp, kind, i});
  };
  add(log.lasers, RecordKind::Laser);
  add(log.imus, RecordKind::Imu);
  add(log.fixes, RecordKind::Gps);
  add(log.baros, RecordKind::Baro);
  add(log.truths, RecordKind::Truth);
  std::stable_sort(records.begin(), records.end(),
                   [](const RecordRef& a, const RecordRef& b) { return a.stamp < b.stamp; });
  return records;
}

void write_mav_log(const std::string& path, const MavLog& log) {
  std::ofstream out(path);
  if (!out) throw MavLogError(path + ": cannot write");
  out << kHeader << '\n' << std::setprecision(10);
  for (const auto& [name, values] : log.meta) {
    out << "META " << name;
    for (double value : values) out << ' ' << value;
    out << '\n';
  }
  for (const RecordRef& record : records_in_time_order(log)) {
    out << std::fixed << std::setprecision(6);
    switch (record.kind) {
      case RecordKind::Laser: {
        const auto& r = log.lasers[record.index];
        out << "LASER " << r.stamp << ' ' << std::setprecision(9) << r.angle_min << ' ' << r.angle_increment << ' '
            << std::setprecision(3) << r.range_min << ' ' << r.range_max << ' ' << r.ranges.size();
        for (float range : r.ranges) std::isinf(range) ? out << " inf" : out << ' ' << range;
        break;
      }
      case RecordKind::Imu:
        out << "IMU " << log.imus[record.index].stamp << std::setprecision(9);
        write_quaternion(out, log.imus[record.index].orientation);
        break;
      case RecordKind::Gps: {
        const auto& r = log.fixes[record.index];
        out << "GPS " << r.stamp << ' ' << std::setprecision(9) << r.latitude << ' ' << r.longitude << ' '
            << std::setprecision(3) << r.altitude << ' ' << r.horizontal_sigma << ' ' << r.vertical_sigma;
        break;
      }
      case RecordKind::Baro:
        out << "BARO " << log.baros[record.index].stamp << ' ' << std::setprecision(2)
            << log.baros[record.index].pressure;
        break;
      case RecordKind::Truth: {
        const auto& r = log.truths[record.index];
        out << "TRUTH " << r.stamp << ' ' << r.position.x() << ' ' << r.position.y() << ' ' << r.position.z()
            << std::setprecision(9);
        write_quaternion(out, r.orientation);
      }
    }
    out << std::defaultfloat << '\n';
  }
  if (!out) throw MavLogError(path + ": write failed");
}

MavLog read_mav_log(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MavLogError(path + ": cannot open");
  MavLog log;
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    const std::string where = path + ":" + std::to_string(number);
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "LASER") {
      log.lasers.push_back(read_laser(words, where));
    } else if (tag == "IMU") {
      ImuRecord r;
      read_values(words, where, r.stamp);
      r.orientation = read_quaternion(words, where);
      log.imus.push_back(r);
    } else if (tag == "GPS") {
      GpsRecord r;
      read_values(words, where, r.stamp, r.latitude, r.longitude, r.altitude, r.horizontal_sigma, r.vertical_sigma);
      log.fixes.push_back(r);
    } else if (tag == "BARO") {
      BaroRecord r;
      read_values(words, where, r.stamp, r.pressure);
      if (!(r.pressure > 0)) throw MavLogError(where + ": pressure must be positive");
      log.baros.push_back(r);
    } else if (tag == "TRUTH") {
      TruthRecord r;
      read_values(words, where, r.stamp, r.position.x(), r.position.y(), r.position.z());
      r.orientation = read_quaternion(words, where);
      log.truths.push_back(r);
    } else if (tag == "META") {
      std::string name;
      words >> name;
      auto& values = log.meta[name];
      for (double value; words >> value;) values.push_back(value);
      if (!words.eof()) throw MavLogError(where + ": META " + name + " has a value that is not a number");
    } else {
      throw MavLogError(where + ": unknown record '" + tag + "'");
    }
  }
  if (log.lasers.empty() && log.imus.empty() && log.baros.empty() && log.fixes.empty())
    throw MavLogError(path + ": no sensor records");
  return log;
}

}  // namespace scanbus::sensor_replay
