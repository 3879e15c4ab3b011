#pragma once

#include "scanbus/service.hpp"

namespace scanbus::pose_estimation {

// Config section `pose_estimation` (config/services/pose_estimation.yaml lists every key):
// rt/scan_match, rt/imu, rt/fix, rt/pressure in; rt/pose, rt/tf (base_link in map) and
// rt/tf_static (laser on base_link) out, one pose per scan match; rt/pose/settled, the same
// poses again once their height left the fusion's window (PoseEstimator::take_settled).
std::unique_ptr<Service> make_pose_estimation(ServiceContext& context);

}  // namespace scanbus::pose_estimation
