#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "scanbus/sim/room_file.hpp"
#include "scanbus/sim/room_generator.hpp"

using namespace scanbus::sim;

namespace {

RoomModel box_room() {
  RoomModel room;
  room.corners = {{0, 0}, {5, 0}, {5, 3}, {0, 3}};
  room.ceiling = 2.5;
  room.scanner = {2, 1, 1};
  return room;
}

}  // namespace

TEST(RoomModel, CastHitsWallsFloorAndCeiling) {
  const RoomModel room = box_room();
  EXPECT_NEAR(*room.cast({1, 0, 0}), 3.0, 1e-9);
  EXPECT_NEAR(*room.cast({-1, 0, 0}), 2.0, 1e-9);
  EXPECT_NEAR(*room.cast({0, 1, 0}), 2.0, 1e-9);
  EXPECT_NEAR(*room.cast({0, 0, -1}), 1.0, 1e-9);
  EXPECT_NEAR(*room.cast({0, 0, 1}), 1.5, 1e-9);
  EXPECT_NEAR(*room.cast(Eigen::Vector3d(1, 0, -1).normalized()), std::sqrt(2.0), 1e-9);  // floor first
}

TEST(RoomModel, HeadingTurnsTheScanner) {
  RoomModel room = box_room();
  room.heading = M_PI / 2;  // scanner x looks along room +y
  EXPECT_NEAR(*room.cast({1, 0, 0}), 2.0, 1e-9);
  EXPECT_TRUE(room.to_room({1, 0, 0}).isApprox(Eigen::Vector3d(2, 2, 1)));
}

TEST(RoomModel, OpeningLetsHorizontalRaysEscapeButNotHigherOnes) {
  RoomModel room = box_room();
  room.openings.push_back({1, 0.5, 1.5, 0.0, 2.0});  // right wall (x = 5), y 0.5..1.5
  EXPECT_FALSE(room.cast({1, 0, 0}).has_value());
  // Steeply up through the door's height: hits the wall above the door (z > 2)? No, the
  // ceiling plane beyond it at z = 2.5.
  const auto up = room.cast(Eigen::Vector3d(3, 0, 1.2).normalized());  // reaches x = 5 at z = 2.2
  ASSERT_TRUE(up.has_value());
  EXPECT_NEAR(room.to_room(*up * Eigen::Vector3d(3, 0, 1.2).normalized()).x(), 5.0, 1e-9);
  // Down through the door: the floor beyond it, as far as the corridor reaches.
  const auto down = room.cast(Eigen::Vector3d(4, 0, -1).normalized());
  ASSERT_TRUE(down.has_value());
  EXPECT_NEAR(room.to_room(*down * Eigen::Vector3d(4, 0, -1).normalized()).z(), 0.0, 1e-9);
  room.outside = 0.5;  // the floor ends 0.5 m past the wall, the ray meets it 1 m past
  EXPECT_FALSE(room.cast(Eigen::Vector3d(4, 0, -1).normalized()).has_value());
}

TEST(RoomModel, BoxesBlockRays) {
  RoomModel room = box_room();
  room.boxes.push_back({{3, 0.5, 0}, {3.5, 1.5, 1.5}});
  EXPECT_NEAR(*room.cast({1, 0, 0}), 1.0, 1e-9);
  EXPECT_NEAR(room.distance_to_surface({1.0, 0, 0}), 0.0, 1e-9);
}

TEST(RoomModel, HorizontalRayPassesOverALowBox) {
  RoomModel room = box_room();
  room.boxes.push_back({{3, 0.5, 0}, {3.5, 1.5, 0.8}});                       // below the scanner's height (1 m)
  const double pitch = M_PI / 2;                                              // cos(pitch) is 6e-17, not 0
  EXPECT_NEAR(*room.cast({std::sin(pitch), 0, std::cos(pitch)}), 3.0, 1e-9);  // the wall, not the box
}

TEST(RoomModel, DistanceToSurface) {
  const RoomModel room = box_room();
  EXPECT_NEAR(room.distance_to_surface({2.9, 0, 0}), 0.1, 1e-9);  // 0.1 m before the x = 5 wall
  EXPECT_NEAR(room.distance_to_surface({0, 0, -0.95}), 0.05, 1e-9);
  EXPECT_NEAR(room.wall_lengths()[1], 3.0, 1e-12);
  EXPECT_NEAR(room.floor_area(), 15.0, 1e-12);
}

TEST(RoomModel, ValidationNamesTheProblem) {
  RoomModel room = box_room();
  room.scanner = {7, 1, 1};
  EXPECT_THROW(room.validate(), std::invalid_argument);
  room = box_room();
  room.openings.push_back({9, 0, 1, 0, 2});
  EXPECT_THROW(room.validate(), std::invalid_argument);
  room = box_room();
  room.scanner.z() = 3.0;
  EXPECT_THROW(room.validate(), std::invalid_argument);
}

TEST(RoomFile, ShippedRoomsLoad) {
  const std::string folder = std::string(SCANBUS_SOURCE_DIR) + "/config/rooms";
  int rooms = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const RoomModel room = load_room_file(entry.path().string());
    EXPECT_GE(room.corners.size(), 4u) << entry.path();
    ++rooms;
  }
  EXPECT_GE(rooms, 3);
  const RoomModel thesis = load_room_file(folder + "/thesis_case1.yaml");
  EXPECT_NEAR(thesis.wall_lengths()[0], 5.47, 1e-12);
  EXPECT_NEAR(thesis.wall_lengths()[1], 3.48, 1e-12);
  EXPECT_NEAR(load_room_file(folder + "/rotated_30.yaml").heading, M_PI / 6, 1e-12);
  EXPECT_NEAR(load_room_file(folder + "/l_shaped.yaml").floor_area(), 6 * 5 - 2.5 * 2, 1e-12);
}

TEST(RoomFile, BadRoomIsAConfigError) {
  const auto error = [](const std::string& yaml) {
    try {
      load_room(scanbus::Config::parse(yaml, "room.yaml"));
    } catch (const scanbus::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("ceiling: 2\nscanner: {position: [1, 1, 1]}\n"), "room.yaml: key 'corners' is required");
  EXPECT_EQ(error("corners: [[0, 0], [1, 0], [1, 1]]\nscanner: {position: [5, 5, 1]}\n"),
            "room.yaml: the scanner stands outside the floor plan");
}

// A generated room written out reads back as the same room: doors with walls behind them,
// windows, furniture, a mixed room's alcove, a built-in unit.
TEST(RoomFile, AGeneratedRoomWrittenOutReadsBack) {
  const auto near = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return (a - b).norm() < 1e-8; };
  size_t outside_walls = 0, boxes = 0;
  for (const auto category : {RoomCategory::Doors, RoomCategory::Windows, RoomCategory::Furniture, RoomCategory::Mixed,
                              RoomCategory::BuiltIn})
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const RoomModel room = generate_room(category, seed).room;
      outside_walls += room.outside_walls.size(), boxes += room.boxes.size();
      const RoomModel back = load_room(scanbus::Config::parse(room_to_yaml(room), "room.yaml"));
      EXPECT_EQ(back.name, room.name);
      ASSERT_EQ(back.corners.size(), room.corners.size());
      for (size_t i = 0; i < room.corners.size(); ++i) EXPECT_LT((back.corners[i] - room.corners[i]).norm(), 1e-8);
      EXPECT_NEAR(back.ceiling, room.ceiling, 1e-8);
      EXPECT_NEAR(back.outside, room.outside, 1e-8);
      EXPECT_NEAR(back.heading, room.heading, 1e-8);
      EXPECT_TRUE(near(back.scanner, room.scanner));
      ASSERT_EQ(back.openings.size(), room.openings.size());
      for (size_t i = 0; i < room.openings.size(); ++i) {
        const Opening &got = back.openings[i], &want = room.openings[i];
        EXPECT_EQ(got.wall, want.wall);
        EXPECT_TRUE(near({got.from, got.to, 0}, {want.from, want.to, 0}));
        EXPECT_TRUE(near({got.bottom, got.top, 0}, {want.bottom, want.top, 0}));
      }
      ASSERT_EQ(back.outside_walls.size(), room.outside_walls.size());
      for (size_t i = 0; i < room.outside_walls.size(); ++i) {
        EXPECT_LT((back.outside_walls[i].from - room.outside_walls[i].from).norm(), 1e-8);
        EXPECT_LT((back.outside_walls[i].to - room.outside_walls[i].to).norm(), 1e-8);
      }
      ASSERT_EQ(back.boxes.size(), room.boxes.size());
      for (size_t i = 0; i < room.boxes.size(); ++i) {
        EXPECT_TRUE(near(back.boxes[i].min, room.boxes[i].min));
        EXPECT_TRUE(near(back.boxes[i].max, room.boxes[i].max));
      }
    }
  EXPECT_GT(outside_walls, 0u);
  EXPECT_GT(boxes, 0u);
}

TEST(RoomModel, OutsideWallsAreSeenThroughOpeningsOnly) {
  RoomModel room = box_room();
  room.openings.push_back({1, 0.5, 1.5, 0.0, 2.0});  // a door in the wall at x = 5
  room.outside_walls.push_back({{7, -2}, {7, 5}});   // a corridor's far side
  EXPECT_NEAR(*room.cast({1, 0, 0}), 5.0, 1e-9);     // through the door
  EXPECT_NEAR(*room.cast(Eigen::Vector3d(1, 0.5, 0).normalized()), 3.0 * std::sqrt(1.25), 1e-9);  // the wall beside it
}

TEST(RoomModel, CastFromAnOffsetOrigin) {
  const RoomModel room = box_room();
  EXPECT_NEAR(*room.cast({0, 0, 0.1}, {0, 0, 1}), 1.4, 1e-9);  // 10 cm up, 10 cm nearer the ceiling
  EXPECT_NEAR(*room.cast({0.5, 0, 0}, {1, 0, 0}), 2.5, 1e-9);
}
