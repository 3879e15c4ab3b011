#include <gtest/gtest.h>

#include <cmath>

#include "scanbus/sim/simulated_scanner.hpp"

using namespace scanbus::sim;

TEST(RoomModel, BuiltInRoomDimensions) {
  const RoomModel room = RoomModel::built_in();
  const auto lengths = room.wall_lengths();
  ASSERT_EQ(lengths.size(), 4u);
  EXPECT_NEAR(lengths[0], 5.2, 1e-9);
  EXPECT_NEAR(lengths[1], 3.9, 1e-9);
  EXPECT_NEAR(room.floor_area(), 5.2 * 3.9, 1e-9);
}

TEST(RoomModel, CastHitsWallsFloorAndCeiling) {
  RoomModel room;
  room.corners = {{-2, -1}, {3, -1}, {3, 2}, {-2, 2}};
  room.floor_z = -1.0;
  room.ceiling_z = 1.5;
  EXPECT_NEAR(*room.cast({1, 0, 0}), 3.0, 1e-9);
  EXPECT_NEAR(*room.cast({-1, 0, 0}), 2.0, 1e-9);
  EXPECT_NEAR(*room.cast({0, 1, 0}), 2.0, 1e-9);
  EXPECT_NEAR(*room.cast({0, 0, -1}), 1.0, 1e-9);
  EXPECT_NEAR(*room.cast({0, 0, 1}), 1.5, 1e-9);
  // 45 degrees down towards the +x wall: the floor (1.0 / sin 45) comes first.
  EXPECT_NEAR(*room.cast(Eigen::Vector3d(1, 0, -1).normalized()), std::sqrt(2.0), 1e-9);
}

TEST(RoomModel, RayThroughAGapEscapes) {
  RoomModel room;
  room.corners = {{1, -1}, {1, 1}};  // a single wall segment, no floor or ceiling hit horizontally
  room.floor_z = -1;
  room.ceiling_z = 1;
  EXPECT_FALSE(room.cast({-1, 0, 0}).has_value());
}

TEST(ScanPattern, ThesisNumbers) {
  ScanPattern pattern;
  pattern.rpm = speed_setting(0).rpm;
  EXPECT_NEAR(pattern.yaw_step() * 180 / M_PI, 1.44, 1e-9);  // Table 4.2, res 0
  EXPECT_EQ(pattern.samples_per_revolution(), 250);
  pattern.rpm = speed_setting(2).rpm;
  EXPECT_NEAR(pattern.yaw_step() * 180 / M_PI, 3.36, 1e-9);
  EXPECT_NEAR(pattern.pitch(0, 0) * 180 / M_PI, 42.0, 1e-9);
  EXPECT_NEAR(pattern.pitch(26, 0) * 180 / M_PI, 120.0, 1e-9);
  EXPECT_NEAR(pattern.pitch(0, 1) * 180 / M_PI, 43.0, 1e-9);
  EXPECT_NEAR(pattern.pitch(0, 3) * 180 / M_PI, 42.0, 1e-9);
  EXPECT_THROW(speed_setting(3), std::invalid_argument);
}

TEST(SimulatedScanner, YawCarriesOverAndRangesMatchTheRoom) {
  ScanPattern pattern;
  SimulatedScanner scanner(RoomModel::built_in(), pattern, 0.0, 1);
  const auto first = scanner.revolution(0, 0);
  const auto second = scanner.revolution(1, 0);
  ASSERT_EQ(first.size(), 150u);
  EXPECT_NEAR(second.front().yaw - first.back().yaw, pattern.yaw_step(), 1e-12);
  EXPECT_GT(second.front().yaw, 2 * M_PI - pattern.yaw_step());
  for (const auto& sample : first) {
    EXPECT_GT(sample.range, 0.5);
    EXPECT_LT(sample.range, 6.0);
  }
}
