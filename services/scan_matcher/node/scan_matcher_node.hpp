#pragma once

#include "scanbus/service.hpp"

namespace scanbus::scan_matcher {

// Config section `scan_matcher` (config/services/scan_matcher.yaml lists every key):
//   use_imu: false              # the IMU's turn between scans as the initial guess
//   laser_axis_in_imu: [0,0,1]  # the laser's z axis in the IMU frame (the axis its scan
//                               # plane turns about): [0,0,1] for a horizontal laser
//   matcher: see MatcherSettings (core/include/scanbus/scan_matcher/pl_icp.hpp)
std::unique_ptr<Service> make_scan_matcher(ServiceContext& context);

}  // namespace scanbus::scan_matcher
