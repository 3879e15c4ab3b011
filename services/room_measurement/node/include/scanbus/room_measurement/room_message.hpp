// RoomResult as DDS messages and back: RoomMeasurement, and the walls' inliers as a PointCloud2
// with a colour per wall (x y z rgb, the layout RViz2 colours by).
#pragma once

#include "scanbus/room_measurement/room_measurement.hpp"
#include "scanbus_msgs/PointCloud2.h"
#include "scanbus_msgs/RoomMeasurement.h"

namespace scanbus::room_measurement {

scanbus::msg::RoomMeasurement to_message(const RoomResult& result, const std::string& frame_id,
                                         const builtin_interfaces::msg::Time& stamp);
// What a RoomMeasurement carries, as a RoomResult (no inliers, no candidates, no error histogram).
RoomResult from_message(const scanbus::msg::RoomMeasurement& message);
sensor_msgs::msg::PointCloud2 walls_cloud(const RoomResult& result, const std::string& frame_id,
                                          const builtin_interfaces::msg::Time& stamp);

}  // namespace scanbus::room_measurement
