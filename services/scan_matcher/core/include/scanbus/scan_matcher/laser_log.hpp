// Laser logs in CARMEN format (FLASER and ROBOTLASER1 lines) and relation files of the
// Freiburg SLAM benchmark (Kuemmerle et al. 2009), and its error metric.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "scanbus/scan_matcher/pose2.hpp"
#include "scanbus/sensor/laser_scan.hpp"

namespace scanbus::scan_matcher {

class LogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LaserRecord {
  sensor::LaserScan scan;  // stamped with the ipc timestamp, s: what relation files refer to
  Pose2 odometry;          // raw wheel odometry (never the corrected pose: that is another SLAM's result)
};

// Every laser line of a CARMEN log; other lines are skipped. Throws LogError naming the
// file and line when a laser line is malformed.
std::vector<LaserRecord> read_carmen_log(const std::string& path);

struct Relation {
  double t1 = 0, t2 = 0;  // ipc timestamps of two scans
  Pose2 motion;           // true pose of t2 in the frame of t1
};

std::vector<Relation> read_relations(const std::string& path);

struct ErrorStats {
  double mean = 0, std = 0, max = 0;
  size_t count = 0;
};

struct RelationErrors {
  ErrorStats translational;  // m
  ErrorStats rotational;     // rad
  size_t missing = 0;        // relations naming a scan that has no estimated pose
};

// For each relation: err = gt^-1 (T(t1)^-1 T(t2)); |err.translation| and |err.yaw|.
// `poses[i]` is the estimate at `stamps[i]`; relations with t2 - t1 > max_span are skipped.
RelationErrors evaluate_relations(const std::vector<double>& stamps, const std::vector<Pose2>& poses,
                                  const std::vector<Relation>& relations, double max_span = 1e18);

}  // namespace scanbus::scan_matcher
