// What the downward-looking laser says about the body's height: the scan matcher's
// increment turned into a height change (section 3.6 of the MAV paper uses the laser's x: it
// looks down), and where each return lies below the body.
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

// One laser return on the ground under the MAV: where it lies in the map's horizontal
// plane and how far below the body's centre (m).
struct GroundReturn {
  Eigen::Vector2d xy;
  double depth;
};

// The return of median depth, none of no returns: a box or a stone among them is outvoted.
std::optional<GroundReturn> median_return(std::vector<GroundReturn> returns);

// A scan's points (in the laser's frame) placed under the body: turned by its attitude and
// set at its horizontal position in the map (m).
std::vector<GroundReturn> ground_returns(const std::vector<Eigen::Vector3d>& points, const Eigen::Quaterniond& attitude,
                                         const Eigen::Vector2d& position, const Eigen::Isometry3d& laser_in_body);

}  // namespace scanbus::pose_estimation
