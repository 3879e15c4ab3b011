// A 2D world of line segments and a laser scanner in it: synthetic scans with known motion
// for the scan matcher's tests and benchmark. The same model serves a horizontal scanner in
// a floor plan and a downward-looking one over a ground profile (x forward, y up).
#pragma once

#include <Eigen/Core>

#include <random>
#include <utility>
#include <vector>

#include "scanbus/scan_matcher/pl_icp.hpp"

namespace scanbus::test_support {

struct LaserModel {
  double angle_min = -M_PI / 2;
  double angle_increment = M_PI / 360;
  int rays = 361;
  double range_max = 30;
  double noise = 0.02;  // m, Gaussian range noise
};

class LaserWorld {
 public:
  using Segment = std::pair<Eigen::Vector2d, Eigen::Vector2d>;
  explicit LaserWorld(std::vector<Segment> segments) : segments_(std::move(segments)) {}

  // A scan from `pose` (the laser's x axis is the middle ray); no return is +inf.
  sensor::LaserScan scan(const scan_matcher::Pose2& pose, const LaserModel& laser, std::mt19937& random) const;

  // A closed polyline's segments.
  static std::vector<Segment> polyline(const std::vector<Eigen::Vector2d>& corners, bool closed);

  // A 7 m x 5 m room with a pillar; a 2 m wide, 30 m corridor with door recesses every 2 m;
  // ground profiles, flat and with 0.3 m steps every 1.5 m, from x = -20 to 60 m at y = 0.
  static LaserWorld room();
  static LaserWorld corridor();
  static LaserWorld flat_ground();
  static LaserWorld stepped_ground();

 private:
  std::vector<Segment> segments_;
};

}  // namespace scanbus::test_support
