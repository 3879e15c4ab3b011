// JSON form of every message (one object per sample, field names as in ROS 2), for
// `scanbus echo` and --json outputs. PointCloud2 data is summarised, not dumped.
#pragma once

#include <nlohmann/json.hpp>

#include "scanbus/messages.hpp"

#define SCANBUS_JSON(Type) void to_json(nlohmann::json& out, const Type& in)

namespace builtin_interfaces::msg {
SCANBUS_JSON(Time);
}
namespace std_msgs::msg {
SCANBUS_JSON(Header);
}
namespace geometry_msgs::msg {
SCANBUS_JSON(Point);
SCANBUS_JSON(Vector3);
SCANBUS_JSON(Quaternion);
SCANBUS_JSON(Pose);
SCANBUS_JSON(PoseStamped);
SCANBUS_JSON(PoseWithCovariance);
SCANBUS_JSON(PoseWithCovarianceStamped);
SCANBUS_JSON(Transform);
SCANBUS_JSON(TransformStamped);
}  // namespace geometry_msgs::msg
namespace tf2_msgs::msg {
SCANBUS_JSON(TFMessage);
}
namespace rosgraph_msgs::msg {
SCANBUS_JSON(Clock);
}
namespace sensor_msgs::msg {
SCANBUS_JSON(LaserScan);
SCANBUS_JSON(PointField);
SCANBUS_JSON(PointCloud2);
SCANBUS_JSON(Imu);
SCANBUS_JSON(FluidPressure);
SCANBUS_JSON(NavSatStatus);
SCANBUS_JSON(NavSatFix);
}  // namespace sensor_msgs::msg
namespace scanbus::msg {
SCANBUS_JSON(Pose2D);
SCANBUS_JSON(SphericalMeasurement);
SCANBUS_JSON(SphericalScan);
SCANBUS_JSON(ScannerCommand);
SCANBUS_JSON(ScannerStatus);
SCANBUS_JSON(ScanMatch);
SCANBUS_JSON(Opening);
SCANBUS_JSON(Wall);
SCANBUS_JSON(RoomMeasurement);
SCANBUS_JSON(AssembleRequest);
SCANBUS_JSON(AssembleReply);
SCANBUS_JSON(Counter);
SCANBUS_JSON(Health);
}  // namespace scanbus::msg

#undef SCANBUS_JSON
