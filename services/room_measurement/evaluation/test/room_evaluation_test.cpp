#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "scanbus/room_evaluation/room_evaluation.hpp"

using namespace scanbus;

TEST(RoomGenerator, EveryCategoryMakesValidRoomsFromSeeds) {
  for (auto category : sim::room_categories()) {
    std::set<double> areas;
    for (unsigned seed = 1; seed <= 20; ++seed) {
      const auto generated = sim::generate_room(category, seed);
      EXPECT_NO_THROW(generated.room.validate()) << sim::category_name(category) << " seed " << seed;
      EXPECT_GT(generated.hardware.errors.lever_arm, 0.0);
      areas.insert(generated.room.floor_area());
    }
    EXPECT_GT(areas.size(), 15u) << sim::category_name(category) << ": seeds should make different rooms";
  }
  const auto a = sim::generate_room(sim::RoomCategory::Doors, 7), b = sim::generate_room(sim::RoomCategory::Doors, 7);
  EXPECT_EQ(a.room.corners, b.room.corners);
  EXPECT_EQ(a.hardware.seed, b.hardware.seed);
}

TEST(RoomGenerator, VisibilityOfAnLFromOneArm) {
  sim::RoomModel room;
  room.corners = {{0, 0}, {6, 0}, {6, 2}, {2, 2}, {2, 6}, {0, 6}};
  room.ceiling = 2.5;
  room.scanner = {5, 1, 1.2};  // in the arm along x: the far end of the other arm is out of sight
  const auto seen = sim::wall_visibility(room);
  ASSERT_EQ(seen.size(), 6u);
  EXPECT_GT(seen[0], 0.9);     // the long wall beside the scanner
  EXPECT_LT(seen[4], 0.05);    // the far end of the other arm
  room.scanner = {1, 1, 1.2};  // in the corner both arms share: every wall in view
  for (double share : sim::wall_visibility(room)) EXPECT_GT(share, 0.5);
}

TEST(RoomEvaluation, SummaryCountsVerdictsAndErrors) {
  room_evaluation::RoomCase good;
  good.verdict = room_evaluation::Verdict::Measured;
  good.measurable = true;
  good.walls = {{3.0, 3.004, 0.005}, {4.0, 4.012, 0.005}};  // 1 sigma, then 2.4 sigma
  good.true_area = 12, good.area = 12.03;
  room_evaluation::RoomCase refused;
  refused.verdict = room_evaluation::Verdict::RefusedWrongly;
  refused.measurable = true;
  const auto summary = room_evaluation::summarize({good, refused}).back();
  EXPECT_EQ(summary.category, "all");
  EXPECT_EQ(summary.rooms, 2u);
  EXPECT_EQ(summary.measured, 1u);
  EXPECT_EQ(summary.refused_wrongly, 1u);
  EXPECT_EQ(summary.within_target, 0u);  // one wall 12 mm off
  EXPECT_EQ(summary.ok_over_2cm, 0u);
  EXPECT_NEAR(summary.max_wall_error, 0.012, 1e-9);
  EXPECT_DOUBLE_EQ(summary.within_1_sigma, 0.5);
  EXPECT_DOUBLE_EQ(summary.within_2_sigma, 0.5);
}

// An alcove seen from the side: its back wall sparse, its sides not found as walls. Its gap
// was an opening and the room ok with the recess cut off ("4 walls" for 8); now refused,
// saying where. A door onto a corridor 1-3 m behind stays an opening.
TEST(RoomEvaluation, ARecessIsRefusedADoorIsAnOpening) {
  const room_measurement::RoomSettings settings;
  const auto alcove = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::Alcove, 5), settings, false);
  EXPECT_EQ(alcove.status, room_measurement::RoomStatus::WallsDoNotClose) << alcove.message;
  EXPECT_NE(alcove.message.find("has a recess"), std::string::npos) << alcove.message;
  EXPECT_EQ(alcove.verdict, room_evaluation::Verdict::Refused);

  size_t doors_measured = 0, doors_openings = 0;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const auto doors =
        room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::Doors, seed), settings, false);
    if (doors.verdict != room_evaluation::Verdict::Measured) continue;
    ++doors_measured;
    for (const auto& wall : doors.measurement.walls) doors_openings += wall.openings.size();
  }
  EXPECT_GE(doors_measured, 4u);
  EXPECT_GE(doors_openings, doors_measured);
}

// A wall whose lower part furniture hides is seen above it, past its inliers' ends (the
// histogram filter drops its short columns); behind the furniture it counts there
// (`enclosing_runs`). Without that, in these generated rooms of the development seeds, the
// furniture's face closed the room (37, 53: ok with wrong walls) or the room was refused
// though its hidden wall could be inferred (59).
TEST(RoomEvaluation, AWallSeenAboveFurnitureCountsBehindIt) {
  const room_measurement::RoomSettings settings;
  for (unsigned seed : {37u, 53u}) {
    const auto mixed = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::Mixed, seed), settings);
    EXPECT_NE(mixed.verdict, room_evaluation::Verdict::Wrong) << "mixed " << seed << ": " << mixed.message;
  }
  const auto mixed = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::Mixed, 59), settings);
  EXPECT_EQ(mixed.verdict, room_evaluation::Verdict::Inferred) << "mixed 59: " << mixed.message;
}

// A T room's shoulders are two walls on one candidate line, on either side of the stem; each
// takes its points between its own corners and its twin's, not across the stem's mouth, where
// the stem's sides cross the line. Scanned by an ideal device (no range bias), the adjustment
// then finds none: with the points across the mouth it fitted -25.5 mm to seed 15, and the
// room came out 2.4 % small.
TEST(RoomEvaluation, ATeeRoomsStemMouthBendsNoWall) {
  const room_measurement::RoomSettings settings;
  sim::GeneratedRoom room = sim::generate_room(sim::RoomCategory::TShape, 15);
  sim::HardwareSettings ideal;
  ideal.seed = room.hardware.seed;
  room.hardware = ideal;
  const auto tee = room_evaluation::evaluate_room(room, settings, false);
  ASSERT_EQ(tee.verdict, room_evaluation::Verdict::Measured) << tee.message;
  EXPECT_LT(std::abs(tee.measurement.device.range_bias), 0.01);
  EXPECT_LT(std::abs(tee.area - tee.true_area) / tee.true_area, 0.005);
}

// Looking into an alcove nearly edge on, the scanner sees one side over under a degree of the
// turn: found among the step's own points, it is too short a run for a wall of the outline,
// and the alcove's back is seen past where a hidden side would stand. The side found there
// stands in for that shadow, and the side is inferred at the front wall's end (seed 7 was
// refused: "a recess ... whose sides are not found as walls").
TEST(RoomEvaluation, AnAlcovesSideSeenEdgeOnStillClosesTheRoom) {
  const auto room = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::Alcove, 7),
                                                   room_measurement::RoomSettings{}, false);
  ASSERT_EQ(room.verdict, room_evaluation::Verdict::Inferred) << room.message;
  EXPECT_LT(std::abs(room.area - room.true_area) / room.true_area, 0.005);
}

// A wardrobe standing out from a wall, its top above where the view ends over it, looks like a
// chimney breast: its front reaches the top of the view, its sides are hidden. Measured as one,
// seed 26's room came out "ok" with walls that are not the room's (the wardrobe's front); a face
// a wardrobe's depth or less out from the wall behind it, under a view that ends below the
// ceiling there, is now refused, saying why.
TEST(RoomEvaluation, AWardrobeUnderTheViewsTopIsNotTakenForAChimneyBreast) {
  const auto room = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::Furniture, 26),
                                                   room_measurement::RoomSettings{}, false);
  EXPECT_NE(room.verdict, room_evaluation::Verdict::Wrong);
  EXPECT_NE(room.message.find("cannot be told apart"), std::string::npos) << room.message;
}

// A scanner 0.7 m from two walls sees the other two 4-7 m away, where the LIDAR-Lite's range
// noise (5-7 cm) is wider than the adjustment's 5 cm band: cut there, the far wall's fit stayed
// where it started (4.3 cm off in this room); the band widens to 2.5 noise sigmas at a point's
// range.
TEST(RoomEvaluation, AFarWallsNoiseIsNotCutAtTheBand) {
  const auto room = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::NearWall, 4),
                                                   room_measurement::RoomSettings{}, false);
  ASSERT_EQ(room.verdict, room_evaluation::Verdict::Measured) << room.message;
  EXPECT_LT(room.max_wall_error(), 0.035);
}

// A cut corner turns under 30 degrees off a neighbour in these rooms (28 in seed 15): a corner
// (30 was the limit). In seeds 56 and 74 the neighbour's points run close to the wall's line
// past the corner (20 and 24 degrees): not the wall running on behind it (clear_of_neighbour).
TEST(RoomEvaluation, AShallowCutCornerIsACorner) {
  for (const unsigned seed : {15u, 24u, 56u, 74u}) {
    const auto room = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::Angled, seed),
                                                     room_measurement::RoomSettings{}, false);
    ASSERT_EQ(room.verdict, room_evaluation::Verdict::Measured) << "seed " << seed << ": " << room.message;
    EXPECT_LT(room.max_wall_error(), 0.02) << "seed " << seed;
  }
}

// RANSAC's plane through the noise either side of a far wall's band, turned 3.5 degrees from
// it, is that wall, not a second one beside it (the room was refused: "neighbouring walls are
// parallel").
TEST(RoomEvaluation, ASliverThroughAFarWallsNoiseIsNoWall) {
  const auto room = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::Doors, 20),
                                                   room_measurement::RoomSettings{}, false);
  ASSERT_EQ(room.verdict, room_evaluation::Verdict::Measured) << room.message;
  EXPECT_LT(room.max_wall_error(), 0.02);
}

// A built-in unit's front near a corner, its side towards the corner and the gap behind it out
// of view, closed on the side wall as an L's inner wall would be (seeds 4 and 7: ok with walls
// that are not the room's): the side wall is seen past the front's end, beyond its line, and
// the room is refused. A door half behind a wardrobe, missed as an opening, shows a corridor
// farther behind its wall than a recess's depth: that room (mixed 35) is still inferred.
TEST(RoomEvaluation, ReturnsBeyondTheOutlineRefuseIt) {
  const room_measurement::RoomSettings settings;
  for (const unsigned seed : {4u, 7u}) {
    const auto room = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::BuiltIn, seed), settings);
    EXPECT_EQ(room.verdict, room_evaluation::Verdict::Refused) << "seed " << seed << ": " << room.message;
    EXPECT_NE(room.message.find("behind that wall's line"), std::string::npos) << room.message;
  }
  const auto mixed = room_evaluation::evaluate_room(sim::generate_room(sim::RoomCategory::Mixed, 35), settings);
  EXPECT_EQ(mixed.verdict, room_evaluation::Verdict::Inferred) << "mixed 35: " << mixed.message;
}

// One unit scans the rooms, as a user's own device: calibrated on some of its scans (the
// unit's terms pooled over them), it measures other rooms better than each scan alone can
// (docs/room_evaluation.md, "What one scan cannot pin down").
TEST(RoomEvaluation, AUnitCalibratedOnItsScansMeasuresOtherRoomsBetter) {
  room_evaluation::SweepOptions options;
  options.count = 26;  // two rooms of each category
  options.unit_seed = 4;
  options.first_seed = 2001;
  room_measurement::RoomSettings settings;
  const auto calibration = room_evaluation::calibrate_on(room_evaluation::evaluate_sweep(options, settings), 4);
  const auto& c = calibration.calibration;
  EXPECT_GE(c.scans, 12u);
  EXPECT_NEAR(c.range_bias, calibration.true_range_bias, 0.0015);
  EXPECT_NEAR(c.lever_arm, calibration.true_lever_arm, 0.0015);

  options.first_seed = 1;
  const auto before = room_evaluation::summarize(room_evaluation::evaluate_sweep(options, settings)).back();
  room_measurement::apply_calibration(c, settings.adjustment);
  const auto after = room_evaluation::summarize(room_evaluation::evaluate_sweep(options, settings)).back();
  // Median 3.3 -> 2.8 mm, p95 11.0 -> 9.7 mm, within target 12 -> 14 of 15 (before each point
  // was weighted by its range noise 3.5 -> 2.7 mm, 10.6 -> 9.9 mm, 11 -> 13).
  EXPECT_LT(after.median_wall_error, 0.9 * before.median_wall_error);
  EXPECT_LT(after.p95_wall_error, before.p95_wall_error);
  EXPECT_GT(after.within_target, before.within_target);
}
