#include "scanbus/room_measurement/room_message.hpp"

#include <cmath>
#include <cstring>

#include "scanbus/palette.hpp"
#include "scanbus/point_cloud.hpp"

namespace scanbus::room_measurement {

// DeviceEstimate::State travels as its value: the IDL's constants in the same order.
namespace constants = scanbus::msg::RoomMeasurement_Constants;
static_assert(static_cast<uint8_t>(DeviceEstimate::State::NotEstimated) == constants::DEVICE_NOT_ESTIMATED);
static_assert(static_cast<uint8_t>(DeviceEstimate::State::Applied) == constants::DEVICE_APPLIED);
static_assert(static_cast<uint8_t>(DeviceEstimate::State::Held) == constants::DEVICE_HELD);

scanbus::msg::RoomMeasurement to_message(const RoomResult& result, const std::string& frame_id,
                                         const builtin_interfaces::msg::Time& stamp) {
  scanbus::msg::RoomMeasurement message;
  message.header().stamp(stamp);
  message.header().frame_id(frame_id);
  for (const auto& wall : result.walls) {
    scanbus::msg::Wall out;
    // a x + b y + c z + d = 0 with the normal pointing away from the scanner.
    out.plane({wall.line.normal.x(), wall.line.normal.y(), 0.0, -wall.line.offset});
    out.length(wall.length);
    out.length_uncertainty(wall.length_sigma);
    out.inliers(static_cast<uint32_t>(wall.points));
    out.rms_residual(wall.line.rms);
    out.inferred(wall.inferred());
    for (const auto& opening : wall.openings) {
      scanbus::msg::Opening o;
      o.start(opening.start);
      o.width(opening.width);
      o.depth(opening.depth);
      out.openings().push_back(o);
    }
    message.walls().push_back(out);
  }
  const double floor_z = result.floor_z.value_or(0.0);
  for (const auto& corner : result.corners) {
    geometry_msgs::msg::Point point;
    point.x(corner.x());
    point.y(corner.y());
    point.z(floor_z);  // corners at floor level, in the scanner frame
    message.corners().push_back(point);
  }
  for (bool inferred : result.corner_inferred) message.corner_inferred().push_back(inferred);
  message.corner_uncertainty(result.corner_sigmas);
  message.floor_area(result.area);
  message.floor_area_uncertainty(result.area_sigma);
  message.perimeter(result.perimeter);
  message.ceiling_height(result.ceiling_height().value_or(std::nan("")));
  message.ceiling_height_note(result.height_note);
  message.status(static_cast<uint8_t>(result.status));
  message.message(result.message);
  message.points_in(static_cast<uint32_t>(result.points_in));
  message.points_valid(static_cast<uint32_t>(result.points_valid));
  message.points_after_filter(static_cast<uint32_t>(result.points_after_filter));
  message.points_after_voxel(static_cast<uint32_t>(result.points_after_voxel));
  message.processing_time(result.elapsed_ms / 1000);
  message.device_state(static_cast<uint8_t>(result.device.state));
  message.range_bias(result.device.range_bias);
  message.lever_arm(result.device.lever_arm);
  message.pitch_offset(result.device.pitch_offset);
  message.yaw_error(result.device.yaw_error);
  return message;
}

RoomResult from_message(const scanbus::msg::RoomMeasurement& message) {
  RoomResult room;
  room.status = static_cast<RoomStatus>(message.status());
  room.message = message.message();
  for (const auto& wall : message.walls()) {
    MeasuredWall out;
    out.line.normal = Eigen::Vector2d(wall.plane()[0], wall.plane()[1]);
    out.line.offset = -wall.plane()[3];
    out.line.rms = wall.rms_residual();
    out.line.inferred = wall.inferred();
    out.length = wall.length();
    out.length_sigma = wall.length_uncertainty();
    out.points = wall.inliers();
    for (const auto& o : wall.openings()) out.openings.push_back({o.start(), o.width(), o.depth()});
    room.walls.push_back(out);
  }
  for (const auto& corner : message.corners()) room.corners.emplace_back(corner.x(), corner.y());
  room.corner_inferred.assign(message.corner_inferred().begin(), message.corner_inferred().end());
  room.corner_sigmas = message.corner_uncertainty();
  room.area = message.floor_area();
  room.area_sigma = message.floor_area_uncertainty();
  room.perimeter = message.perimeter();
  if (std::isfinite(message.ceiling_height())) {
    room.floor_z = 0;
    room.ceiling_z = message.ceiling_height();
  }
  room.height_note = message.ceiling_height_note();
  room.points_in = message.points_in();
  room.points_valid = message.points_valid();
  room.points_after_filter = message.points_after_filter();
  room.points_after_voxel = message.points_after_voxel();
  room.elapsed_ms = message.processing_time() * 1000;
  const uint8_t state = message.device_state();
  room.device = {
      state <= constants::DEVICE_HELD ? static_cast<DeviceEstimate::State>(state) : DeviceEstimate::State::NotEstimated,
      message.range_bias(), message.lever_arm(), message.pitch_offset(), message.yaw_error()};
  return room;
}

sensor_msgs::msg::PointCloud2 walls_cloud(const RoomResult& result, const std::string& frame_id,
                                          const builtin_interfaces::msg::Time& stamp) {
  std::vector<Eigen::Vector3f> points;
  std::vector<uint32_t> colours;
  for (size_t w = 0; w < result.walls.size(); ++w) {
    for (const auto& p : result.walls[w].line.inliers) {
      points.push_back(p);
      colours.push_back(wall_colour(w));
    }
  }
  return to_coloured_point_cloud2(points, colours, frame_id, stamp);
}

}  // namespace scanbus::room_measurement
