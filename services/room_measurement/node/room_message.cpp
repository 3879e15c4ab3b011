#include "scanbus/room_measurement/room_message.hpp"

#include <cmath>
#include <cstring>

#include "scanbus/point_cloud.hpp"

namespace scanbus::room_measurement {

uint32_t wall_colour(size_t index) {
  static const uint32_t kPalette[] = {0xE6194B, 0x3CB44B, 0x4363D8, 0xF58231, 0x911EB4,
                                      0x42D4F4, 0xF032E6, 0x9A6324, 0x469990, 0x808000};
  return kPalette[index % (sizeof(kPalette) / sizeof(kPalette[0]))];
}

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
  message.floor_area(result.area);
  message.perimeter(result.perimeter);
  message.ceiling_height(result.ceiling_height().value_or(std::nan("")));
  message.status(static_cast<uint8_t>(result.status));
  message.message(result.message);
  return message;
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
