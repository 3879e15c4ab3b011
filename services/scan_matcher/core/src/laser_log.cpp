#include "scanbus/scan_matcher/laser_log.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace scanbus::scan_matcher {

namespace {

template <class T>
void take(std::istringstream& words, T& value, const std::string& where, const char* what) {
  if (!(words >> value)) throw LogError(where + ": cannot read " + what);
}

LaserRecord parse_flaser(std::istringstream& words, const std::string& where) {
  LaserRecord record;
  size_t count = 0;
  take(words, count, where, "the number of ranges");
  if (count < 2 || count > 100000) throw LogError(where + ": implausible number of ranges " + std::to_string(count));
  record.scan.ranges.resize(count);
  for (auto& range : record.scan.ranges) take(words, range, where, "a range");
  Pose2 corrected;
  take(words, corrected.x, where, "x");
  take(words, corrected.y, where, "y");
  take(words, corrected.theta, where, "theta");
  take(words, record.odometry.x, where, "odom_x");
  take(words, record.odometry.y, where, "odom_y");
  take(words, record.odometry.theta, where, "odom_theta");
  take(words, record.scan.stamp, where, "ipc_timestamp");
  // FLASER is a 180 degree front laser (SICK LMS): -90 to +90 degrees.
  record.scan.angle_min = -M_PI / 2;
  record.scan.angle_increment = M_PI / static_cast<double>(count - 1);
  record.scan.range_max = *std::max_element(record.scan.ranges.begin(), record.scan.ranges.end());
  return record;
}

LaserRecord parse_robotlaser(std::istringstream& words, const std::string& where) {
  LaserRecord record;
  int laser_type = 0, remission_mode = 0;
  double field_of_view = 0, accuracy = 0;
  size_t count = 0, remissions = 0;
  take(words, laser_type, where, "laser_type");
  take(words, record.scan.angle_min, where, "start_angle");
  take(words, field_of_view, where, "field_of_view");
  take(words, record.scan.angle_increment, where, "angular_resolution");
  take(words, record.scan.range_max, where, "maximum_range");
  take(words, accuracy, where, "accuracy");
  take(words, remission_mode, where, "remission_mode");
  take(words, count, where, "num_readings");
  if (count < 2 || count > 100000) throw LogError(where + ": implausible number of ranges " + std::to_string(count));
  record.scan.ranges.resize(count);
  for (auto& range : record.scan.ranges) take(words, range, where, "a range");
  take(words, remissions, where, "num_remissions");
  double ignored = 0;
  for (size_t i = 0; i < remissions; ++i) take(words, ignored, where, "a remission");
  for (int i = 0; i < 3; ++i) take(words, ignored, where, "the laser pose");
  take(words, record.odometry.x, where, "robot_pose_x");
  take(words, record.odometry.y, where, "robot_pose_y");
  take(words, record.odometry.theta, where, "robot_pose_theta");
  for (int i = 0; i < 5; ++i) take(words, ignored, where, "velocities and safety distances");
  take(words, record.scan.stamp, where, "timestamp");
  return record;
}

double mean_of(const std::vector<double>& values) {
  double sum = 0;
  for (double v : values) sum += v;
  return values.empty() ? 0 : sum / static_cast<double>(values.size());
}

ErrorStats stats_of(const std::vector<double>& values) {
  ErrorStats stats;
  stats.count = values.size();
  if (values.empty()) return stats;
  stats.mean = mean_of(values);
  double squares = 0;
  for (double v : values) {
    squares += (v - stats.mean) * (v - stats.mean);
    stats.max = std::max(stats.max, v);
  }
  stats.std = std::sqrt(squares / static_cast<double>(values.size()));
  return stats;
}

}  // namespace

std::vector<LaserRecord> read_carmen_log(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw LogError(path + ": cannot open");
  std::vector<LaserRecord> records;
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    const std::string where = path + ":" + std::to_string(number);
    if (tag == "FLASER") records.push_back(parse_flaser(words, where));
    if (tag == "ROBOTLASER1") records.push_back(parse_robotlaser(words, where));
  }
  if (records.empty()) throw LogError(path + ": no FLASER or ROBOTLASER1 lines");
  return records;
}

std::vector<Relation> read_relations(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw LogError(path + ": cannot open");
  std::vector<Relation> relations;
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    std::istringstream words(line);
    Relation relation;
    double z, roll, pitch;
    if (!(words >> relation.t1 >> relation.t2 >> relation.motion.x >> relation.motion.y >> z >> roll >> pitch >>
          relation.motion.theta))
      throw LogError(path + ":" + std::to_string(number) + ": expected 't1 t2 x y z roll pitch yaw'");
    relations.push_back(relation);
  }
  if (relations.empty()) throw LogError(path + ": no relations");
  return relations;
}

RelationErrors evaluate_relations(const std::vector<double>& stamps, const std::vector<Pose2>& poses,
                                  const std::vector<Relation>& relations, double max_span) {
  auto pose_at = [&](double stamp) -> const Pose2* {
    const auto found = std::lower_bound(stamps.begin(), stamps.end(), stamp - 1e-4);
    if (found == stamps.end() || std::abs(*found - stamp) > 1e-4) return nullptr;
    return &poses[static_cast<size_t>(found - stamps.begin())];
  };
  RelationErrors errors;
  std::vector<double> translational, rotational;
  for (const auto& relation : relations) {
    if (relation.t2 - relation.t1 > max_span) continue;
    const Pose2* a = pose_at(relation.t1);
    const Pose2* b = pose_at(relation.t2);
    if (!a || !b) {
      ++errors.missing;
      continue;
    }
    const Pose2 error = relation.motion.inverse() * (a->inverse() * *b);
    translational.push_back(error.distance());
    rotational.push_back(std::abs(error.theta));
  }
  errors.translational = stats_of(translational);
  errors.rotational = stats_of(rotational);
  return errors;
}

}  // namespace scanbus::scan_matcher
