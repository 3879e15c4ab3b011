// The scan matcher's increment of a laser rigidly mounted on the body, turned into the
// body's height change (section 3.6 of the MAV paper uses the laser's x: it looks down).
#pragma once

#include <Eigen/Geometry>

namespace scanbus::pose_estimation {

// `dx`, `dy`: the laser's motion in its own scan plane (the ScanMatch increment), expressed
// in its frame at the earlier scan; the attitudes are the body's in the map frame at the two
// scans. Motion along the laser's z axis is invisible to it and left out.
double height_change(double dx, double dy, const Eigen::Quaterniond& attitude_before,
                     const Eigen::Quaterniond& attitude_after, const Eigen::Isometry3d& laser_in_body);

}  // namespace scanbus::pose_estimation
