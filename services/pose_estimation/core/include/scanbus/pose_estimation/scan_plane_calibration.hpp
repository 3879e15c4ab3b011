// The laser's rotation within its own scan plane, away from its mount's drawing, calibrated
// from a flight that turns on the spot (a hover-turn) over any fixed ground.
//
// Why this rotation alone: at a constant heading it tilts the ground cloud across the flight
// exactly as a sloped ground would, so no height estimate tells them apart (docs/performance.md,
// "the tilt a misaligned mount leaves"); the mount's two other rotations move the cloud along
// or around the down axis by millimetres.
//
// How: a scan line through a fixed spot, seen again from the opposite heading, is the same line
// reversed, so its slope along the body's y axis changes sign: over a turn the ground adds only
// odd harmonics of the heading, whatever its shape. A rotation of the laser in its scan plane
// adds the same slope at every heading. The part of the slope that does not turn with the
// heading is the rotation; one estimate per whole turn, their spread gives the sigma.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <vector>

#include "scanbus/sensor/laser_scan.hpp"

namespace scanbus::pose_estimation {

struct AttitudeSample {  // base_link in the map frame (the IMU's attitude)
  double stamp = 0;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

struct ScanPlaneCalibrationSettings {
  sensor::RangeGate gate{0, 30.0, M_PI / 2};  // the rays kept (the MAV paper's 30 m and 90 degrees)
  int min_turns = 3;                          // whole turns: the sigma is the spread of one estimate per turn
  double max_attitude_gap = 0.25;             // s between the IMU samples a scan lies between
  // m: the median scan's points about their line. On level, even ground they scatter by the range
  // noise alone (a UTM-30LX class scanner: +-30 mm, about 0.02 m one sigma); over rough ground,
  // steps or mounds each turn sees the same relief from a slightly drifted spot, and the turns'
  // spread no longer tells the error (docs/performance.md): refused, calibrate over a car park.
  double max_line_residual = 0.05;
};

struct ScanPlaneCalibration {
  bool ok = false;
  std::string status;          // what was measured, or why it could not be
  double rotation = NAN;       // rad about the laser's z axis (its scan plane's normal), after the drawing
  double sigma = NAN;          // rad, one standard deviation of `rotation`
  std::vector<double> turns;   // rad, the estimate of each whole turn
  size_t scans = 0;            // scans used
  double line_residual = NAN;  // m, the median scan's points about their line: how even the ground is
};

ScanPlaneCalibration calibrate_scan_plane(const std::vector<sensor::LaserScan>& scans,
                                          const std::vector<AttitudeSample>& attitudes,
                                          const Eigen::Isometry3d& laser_in_body,
                                          const ScanPlaneCalibrationSettings& settings = {});

// The mount as drawn, turned by a calibrated rotation within its scan plane.
Eigen::Isometry3d turned_in_scan_plane(const Eigen::Isometry3d& laser_in_body, double rotation);

}  // namespace scanbus::pose_estimation
