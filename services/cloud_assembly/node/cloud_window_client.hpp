// The client side of cloud_assembly's request-reply (rt/cloud/assemble_request and
// _reply), like the MAV paper's laser_assembler client.
#pragma once

#include <optional>
#include <string>

#include "scanbus/dds.hpp"
#include "scanbus_msgs/PointCloud2.h"

namespace scanbus::cloud_assembly {

// The cloud of the scans stamped in [begin, end] (s since the epoch), in the fixed frame;
// none, with the reason in `problem`, when nobody answers within `timeout` s or the reply
// is empty or refused.
std::optional<sensor_msgs::msg::PointCloud2> request_window_cloud(Participant& participant, double begin, double end,
                                                                  double timeout, std::string& problem);

}  // namespace scanbus::cloud_assembly
