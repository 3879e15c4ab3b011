#include <gtest/gtest.h>

#include "scanbus/room_measurement/room_message.hpp"
#include "scanbus_msgs/RoomMeasurementPubSubTypes.h"

using namespace scanbus::room_measurement;

namespace {

RoomResult measured_room() {
  RoomResult room;
  room.message = "measured";
  MeasuredWall wall;
  wall.line.normal = Eigen::Vector2d(0.6, 0.8);
  wall.line.offset = 2.5;
  wall.line.rms = 0.004;
  wall.length = 3.48;
  wall.length_sigma = 0.006;
  wall.points = 812;
  wall.openings = {{0.70, 0.90, 2.35}, {2.10, 0.60, 0.0}};
  room.walls = {wall, wall};
  room.walls[1].line.inferred = true;
  room.walls[1].openings.clear();
  room.corners = {{1.0, 2.0}, {-1.5, 2.0}};
  room.corner_inferred = {false, true};
  room.corner_sigmas = {0.004, 0.011};
  room.area = 19.03;
  room.area_sigma = 0.04;
  room.perimeter = 17.9;
  room.floor_z = -1.2;
  room.ceiling_z = 1.4;
  room.points_in = 18560;
  room.points_valid = 18400;
  room.points_after_filter = 12000;
  room.points_after_voxel = 9000;
  room.elapsed_ms = 11.5;
  room.device = {DeviceEstimate::State::Held, 0.064, -0.012, 0.003, 0.024};
  return room;
}

}  // namespace

// What the service publishes reaches a subscriber whole: the result goes through the CDR bytes
// on the wire and back (openings with their depth, inferred walls and corners, point counts, the device terms).
TEST(RoomMessage, TheResultSurvivesTheWire) {
  const RoomResult sent = measured_room();
  builtin_interfaces::msg::Time stamp;
  stamp.sec(12);
  scanbus::msg::RoomMeasurement message = to_message(sent, "scanner", stamp);
  scanbus::msg::RoomMeasurementPubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&message)());
  ASSERT_TRUE(type.serialize(&message, &payload));
  scanbus::msg::RoomMeasurement received;
  ASSERT_TRUE(type.deserialize(&payload, &received));
  const RoomResult room = from_message(received);

  EXPECT_EQ(received.header().frame_id(), "scanner");
  EXPECT_EQ(room.message, "measured");
  ASSERT_EQ(room.walls.size(), 2u);
  EXPECT_NEAR(room.walls[0].line.normal.x(), 0.6, 1e-12);
  EXPECT_NEAR(room.walls[0].line.offset, 2.5, 1e-12);
  EXPECT_NEAR(room.walls[0].length, 3.48, 1e-12);
  EXPECT_NEAR(room.walls[0].length_sigma, 0.006, 1e-12);
  EXPECT_EQ(room.walls[0].points, 812u);
  ASSERT_EQ(room.walls[0].openings.size(), 2u);
  EXPECT_NEAR(room.walls[0].openings[0].start, 0.70, 1e-12);
  EXPECT_NEAR(room.walls[0].openings[0].width, 0.90, 1e-12);
  EXPECT_NEAR(room.walls[0].openings[0].depth, 2.35, 1e-12);
  EXPECT_EQ(room.walls[0].openings[1].depth, 0.0);
  EXPECT_FALSE(room.walls[0].inferred());
  EXPECT_TRUE(room.walls[1].inferred());
  EXPECT_EQ(room.corner_inferred, (std::vector<bool>{false, true}));
  EXPECT_EQ(room.corner_sigmas, (std::vector<double>{0.004, 0.011}));
  EXPECT_NEAR(room.area, 19.03, 1e-12);
  EXPECT_NEAR(room.area_sigma, 0.04, 1e-12);
  ASSERT_TRUE(room.ceiling_height());
  EXPECT_NEAR(*room.ceiling_height(), 2.6, 1e-12);
  EXPECT_EQ(room.points_in, 18560u);
  EXPECT_EQ(room.points_after_voxel, 9000u);
  EXPECT_NEAR(room.elapsed_ms, 11.5, 1e-9);
  EXPECT_EQ(room.device.state, DeviceEstimate::State::Held);
  EXPECT_NEAR(room.device.range_bias, 0.064, 1e-12);
  EXPECT_NEAR(room.device.lever_arm, -0.012, 1e-12);
  EXPECT_NEAR(room.device.pitch_offset, 0.003, 1e-12);
  EXPECT_NEAR(room.device.yaw_error, 0.024, 1e-12);
}

// A room without a ceiling height says why, and the subscriber gets the reason, not a number.
TEST(RoomMessage, AMissingCeilingHeightStaysMissing) {
  RoomResult sent = measured_room();
  sent.ceiling_z.reset();
  sent.height_note = "ceiling not seen";
  const RoomResult room = from_message(to_message(sent, "scanner", {}));
  EXPECT_FALSE(room.ceiling_height());
  EXPECT_EQ(room.height_note, "ceiling not seen");
}
