// Room measurement on simulated scans of the shipped rooms (2 cm range noise): every wall
// length within 1 cm and the area within 0.5 % of the room model.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "scanbus/room_evaluation/simulated_scan.hpp"
#include "scanbus/room_measurement/room_measurement.hpp"
#include "scanbus/sim/room_file.hpp"

using namespace scanbus;

namespace {

sim::RoomModel room(const std::string& name) {
  return sim::load_room_file(std::string(SCANBUS_SOURCE_DIR) + "/config/rooms/" + name + ".yaml");
}

// Wall i of the model runs from corner i to i + 1, in room coordinates; the measurement
// is in the scanner frame. Match each measured wall to the model wall whose line it is.
void expect_accurate(const std::string& name) {
  const sim::RoomModel model = room(name);
  const auto points = room_evaluation::simulated_scan(model, {});
  const auto result = room_measurement::measure_room(points, room_measurement::RoomSettings{});
  ASSERT_EQ(result.status, room_measurement::RoomStatus::Ok) << result.message;
  ASSERT_EQ(result.walls.size(), model.corners.size()) << name;
  const auto truth = model.wall_lengths();
  for (const auto& wall : result.walls) {
    // The model wall this measured wall lies on: its midpoint's nearest model wall.
    const Eigen::Vector2d mid_scanner =
        wall.line.normal * wall.line.offset + wall.line.direction() * (wall.line.start + wall.line.end) / 2;
    const Eigen::Vector3d mid = model.to_room(Eigen::Vector3d(mid_scanner.x(), mid_scanner.y(), 0));
    size_t best = 0;
    double best_distance = 1e9;
    for (size_t i = 0; i < model.corners.size(); ++i) {
      const Eigen::Vector2d a = model.corners[i], b = model.corners[(i + 1) % model.corners.size()];
      const double s = std::clamp((mid.head<2>() - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      const double d = (mid.head<2>() - (a + s * (b - a))).norm();
      if (d < best_distance) best_distance = d, best = i;
    }
    std::printf("%s: wall %.4f m (true %.4f, +-%.4f, rms %.4f, %zu inliers)\n", name.c_str(), wall.length, truth[best],
                wall.length_sigma, wall.line.rms, wall.points);
    EXPECT_NEAR(wall.length, truth[best], 0.01) << name << " wall " << best;
  }
  std::printf("%s: area %.4f m2 (true %.4f), %zu points in, %zu after filter, %.1f ms\n", name.c_str(), result.area,
              model.floor_area(), result.points_in, result.points_after_filter, result.elapsed_ms);
  EXPECT_NEAR(result.area, model.floor_area(), 0.005 * model.floor_area()) << name;
  ASSERT_TRUE(result.ceiling_height().has_value());
  EXPECT_NEAR(*result.ceiling_height(), model.ceiling, 0.02) << name;
}

}  // namespace

TEST(RoomAccuracy, ThesisCase1) { expect_accurate("thesis_case1"); }
TEST(RoomAccuracy, LShaped) { expect_accurate("l_shaped"); }
TEST(RoomAccuracy, Rotated30) { expect_accurate("rotated_30"); }
