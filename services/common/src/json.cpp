#include "scanbus/json.hpp"

using nlohmann::json;

namespace builtin_interfaces::msg {
void to_json(json& out, const Time& in) { out = {{"sec", in.sec()}, {"nanosec", in.nanosec()}}; }
}  // namespace builtin_interfaces::msg

namespace std_msgs::msg {
void to_json(json& out, const Header& in) { out = {{"stamp", in.stamp()}, {"frame_id", in.frame_id()}}; }
}  // namespace std_msgs::msg

namespace geometry_msgs::msg {
void to_json(json& out, const Point& in) { out = {{"x", in.x()}, {"y", in.y()}, {"z", in.z()}}; }
void to_json(json& out, const Vector3& in) { out = {{"x", in.x()}, {"y", in.y()}, {"z", in.z()}}; }
void to_json(json& out, const Quaternion& in) { out = {{"x", in.x()}, {"y", in.y()}, {"z", in.z()}, {"w", in.w()}}; }
void to_json(json& out, const Pose& in) { out = {{"position", in.position()}, {"orientation", in.orientation()}}; }
void to_json(json& out, const PoseStamped& in) { out = {{"header", in.header()}, {"pose", in.pose()}}; }
void to_json(json& out, const PoseWithCovariance& in) { out = {{"pose", in.pose()}, {"covariance", in.covariance()}}; }
void to_json(json& out, const PoseWithCovarianceStamped& in) { out = {{"header", in.header()}, {"pose", in.pose()}}; }
void to_json(json& out, const Transform& in) { out = {{"translation", in.translation()}, {"rotation", in.rotation()}}; }
void to_json(json& out, const TransformStamped& in) {
  out = {{"header", in.header()}, {"child_frame_id", in.child_frame_id()}, {"transform", in.transform()}};
}
}  // namespace geometry_msgs::msg

namespace tf2_msgs::msg {
void to_json(json& out, const TFMessage& in) { out = {{"transforms", in.transforms()}}; }
}  // namespace tf2_msgs::msg

namespace rosgraph_msgs::msg {
void to_json(json& out, const Clock& in) { out = {{"clock", in.clock()}}; }
}  // namespace rosgraph_msgs::msg

namespace sensor_msgs::msg {
void to_json(json& out, const LaserScan& in) {
  out = {{"header", in.header()},
         {"angle_min", in.angle_min()},
         {"angle_max", in.angle_max()},
         {"angle_increment", in.angle_increment()},
         {"time_increment", in.time_increment()},
         {"scan_time", in.scan_time()},
         {"range_min", in.range_min()},
         {"range_max", in.range_max()},
         {"ranges", in.ranges()},
         {"intensities", in.intensities()}};
}
void to_json(json& out, const PointField& in) {
  out = {{"name", in.name()}, {"offset", in.offset()}, {"datatype", in.datatype()}, {"count", in.count()}};
}
// The cloud's bytes summed: tells two clouds apart without printing megabytes.
static uint64_t data_sum(const std::vector<uint8_t>& data) {
  uint64_t sum = 0;
  for (const uint8_t byte : data) sum += byte;
  return sum;
}

void to_json(json& out, const PointCloud2& in) {
  out = {{"header", in.header()},
         {"height", in.height()},
         {"width", in.width()},
         {"fields", in.fields()},
         {"is_bigendian", in.is_bigendian()},
         {"point_step", in.point_step()},
         {"row_step", in.row_step()},
         {"data", {{"bytes", in.data().size()}, {"sum", data_sum(in.data())}}},
         {"is_dense", in.is_dense()}};
}
void to_json(json& out, const Imu& in) {
  out = {{"header", in.header()},
         {"orientation", in.orientation()},
         {"orientation_covariance", in.orientation_covariance()},
         {"angular_velocity", in.angular_velocity()},
         {"angular_velocity_covariance", in.angular_velocity_covariance()},
         {"linear_acceleration", in.linear_acceleration()},
         {"linear_acceleration_covariance", in.linear_acceleration_covariance()}};
}
void to_json(json& out, const FluidPressure& in) {
  out = {{"header", in.header()}, {"fluid_pressure", in.fluid_pressure()}, {"variance", in.variance()}};
}
void to_json(json& out, const NavSatStatus& in) { out = {{"status", in.status()}, {"service", in.service()}}; }
void to_json(json& out, const NavSatFix& in) {
  out = {{"header", in.header()},
         {"status", in.status()},
         {"latitude", in.latitude()},
         {"longitude", in.longitude()},
         {"altitude", in.altitude()},
         {"position_covariance", in.position_covariance()},
         {"position_covariance_type", in.position_covariance_type()}};
}
}  // namespace sensor_msgs::msg

namespace scanbus::msg {
void to_json(json& out, const Pose2D& in) { out = {{"x", in.x()}, {"y", in.y()}, {"theta", in.theta()}}; }
void to_json(json& out, const SphericalMeasurement& in) {
  out = {{"stamp", in.stamp()}, {"line", in.line()},   {"yaw", in.yaw()},
         {"pitch", in.pitch()}, {"range", in.range()}, {"signal", in.signal()}};
}
void to_json(json& out, const SphericalScan& in) {
  out = {{"header", in.header()},
         {"revolution", in.revolution()},
         {"first_sequence", in.first_sequence()},
         {"last_sequence", in.last_sequence()},
         {"lost", in.lost()},
         {"revolution_complete", in.revolution_complete()},
         {"measurements", in.measurements()}};
}
void to_json(json& out, const ScannerCommand& in) {
  out = {{"header", in.header()}, {"command", in.command()}, {"resolution", in.resolution()}};
}
void to_json(json& out, const ScannerStatus& in) {
  out = {{"header", in.header()},
         {"device", in.device()},
         {"firmware", in.firmware()},
         {"state", in.state()},
         {"resolution", in.resolution()},
         {"rpm", in.rpm()},
         {"revolutions", in.revolutions()},
         {"measurements", in.measurements()},
         {"lost_lines", in.lost_lines()},
         {"checksum_errors", in.checksum_errors()},
         {"malformed_lines", in.malformed_lines()},
         {"out_of_range", in.out_of_range()},
         {"aborted_scans", in.aborted_scans()},
         {"message", in.message()}};
}
void to_json(json& out, const ScanMatch& in) {
  out = {{"header", in.header()},
         {"pose", in.pose()},
         {"increment", in.increment()},
         {"covariance", in.covariance()},
         {"quality", in.quality()},
         {"iterations", in.iterations()},
         {"correspondences", in.correspondences()},
         {"residual", in.residual()},
         {"keyframe", in.keyframe()}};
}
void to_json(json& out, const Opening& in) {
  out = {{"start", in.start()}, {"width", in.width()}, {"depth", in.depth()}};
}
void to_json(json& out, const Wall& in) {
  out = {{"plane", in.plane()},
         {"length", in.length()},
         {"length_uncertainty", in.length_uncertainty()},
         {"inliers", in.inliers()},
         {"rms_residual", in.rms_residual()},
         {"inferred", in.inferred()},
         {"openings", in.openings()}};
}
void to_json(json& out, const RoomMeasurement& in) {
  out = {{"header", in.header()},
         {"walls", in.walls()},
         {"corners", in.corners()},
         {"corner_inferred", in.corner_inferred()},
         {"corner_uncertainty", in.corner_uncertainty()},
         {"floor_area", in.floor_area()},
         {"floor_area_uncertainty", in.floor_area_uncertainty()},
         {"perimeter", in.perimeter()},
         {"ceiling_height", in.ceiling_height()},
         {"ceiling_height_note", in.ceiling_height_note()},
         {"status", in.status()},
         {"message", in.message()},
         {"points_in", in.points_in()},
         {"points_valid", in.points_valid()},
         {"points_after_filter", in.points_after_filter()},
         {"points_after_voxel", in.points_after_voxel()},
         {"processing_time", in.processing_time()},
         {"device_state", in.device_state()},
         {"range_bias", in.range_bias()},
         {"lever_arm", in.lever_arm()},
         {"pitch_offset", in.pitch_offset()},
         {"yaw_error", in.yaw_error()}};
}
void to_json(json& out, const AssembleRequest& in) {
  out = {{"request_id", in.request_id()},
         {"client", in.client()},
         {"begin", in.begin()},
         {"end", in.end()},
         {"frame_id", in.frame_id()}};
}
void to_json(json& out, const AssembleReply& in) {
  out = {{"request_id", in.request_id()},
         {"client", in.client()},
         {"status", in.status()},
         {"message", in.message()},
         {"cloud", in.cloud()}};
}
void to_json(json& out, const Counter& in) { out = {{"name", in.name()}, {"value", in.value()}}; }
void to_json(json& out, const Health& in) {
  out = {{"header", in.header()},     {"service", in.service()},      {"host", in.host()},
         {"pid", in.pid()},           {"state", in.state()},          {"uptime", in.uptime()},
         {"counters", in.counters()}, {"last_error", in.last_error()}};
}
}  // namespace scanbus::msg
