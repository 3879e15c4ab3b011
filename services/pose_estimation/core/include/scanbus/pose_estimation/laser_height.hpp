// What the downward-looking laser says about the body's height: the scan matcher's
// increment turned into a height change (section 3.6 of the MAV paper uses the laser's x: it
// looks down), and the clearance above the ground line the scan itself shows.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <optional>
#include <vector>

namespace scanbus::pose_estimation {

// `dx`, `dy`: the laser's motion in its own scan plane (the ScanMatch increment), expressed
// in its frame at the earlier scan; the attitudes are the body's in the map frame at the two
// scans. Motion along the laser's z axis is invisible to it and left out.
double height_change(double dx, double dy, const Eigen::Quaterniond& attitude_before,
                     const Eigen::Quaterniond& attitude_after, const Eigen::Isometry3d& laser_in_body);

// The line most of a scan's points lie on, in the laser's scan plane: normal . p = distance,
// the normal pointing from the laser towards the line (distance > 0).
struct GroundLine {
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();
  double distance = 0;  // m
  size_t inliers = 0;
};

struct GroundLineSettings {
  double inlier_distance = 0.05;  // m from the line (the laser's noise is 2 cm)
  double min_inlier_share = 0.5;  // of the scan's points: less is no ground line
  size_t min_points = 20;
  double max_slope = 5 * M_PI / 180;  // rad from level in the map frame: steeper is no ground
                                      // (a line across a block's edge, a wall)
};

// RANSAC over point pairs half a scan apart (deterministic: the same scan gives the same
// line), refined by a total least-squares fit to the inliers. Raised objects (boxes,
// blocks) take a minority of the points and are left out. None when no line holds
// `min_inlier_share` of the points.
std::optional<GroundLine> fit_ground_line(const std::vector<Eigen::Vector2d>& points,
                                          const GroundLineSettings& settings = {});

// The body's height above the ground the line lies on (m): the line's distance turned by
// the attitude into vertical, less the laser's lever below the body's centre. Rolling within
// the scan plane does not change it; an attitude error enters only to second order. None
// when the line, turned into the map frame, is steeper than `max_slope` (rad).
std::optional<double> ground_clearance(const GroundLine& line, const Eigen::Quaterniond& attitude,
                                       const Eigen::Isometry3d& laser_in_body, double max_slope);

}  // namespace scanbus::pose_estimation
