// The room measurement on the seeded sweep of `scanbus eval rooms` (130 rooms, 13 categories,
// each with a device's imperfections). Guards what holds today (docs/room_evaluation.md) and
// the sigmas' calibration; the accuracy targets (every wall within 1 cm, none ok with a wall
// 2 cm off) are not met yet: the shares that meet them are guarded instead.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "scanbus/room_evaluation/room_evaluation.hpp"

using namespace scanbus;

TEST(RoomSweep, WhatHoldsOnTheSweep) {
  room_evaluation::SweepOptions options;
  options.threads =
      1;  // ctest -j2 runs timing-sensitive service tests beside it (cli_demo lost poses under the sanitizers)
  const auto cases = room_evaluation::evaluate_sweep(options, room_measurement::RoomSettings{});
  ASSERT_EQ(cases.size(), 130u);
  for (const auto& s : room_evaluation::summarize(cases)) {
    std::printf(
        "%-15s rooms %zu seen %zu measured %zu inferred %zu wrong %zu refused %zu/%zu median %.4f p95 %.4f max %.4f m, "
        "%.0f %% within 1 sigma, %.0f %% within 2, openings %zu/%zu (%zu spurious, median edge %.3f m)\n",
        s.category.c_str(), s.rooms, s.measurable, s.measured, s.inferred, s.wrong, s.refused, s.refused_wrongly,
        s.median_wall_error, s.p95_wall_error, s.max_wall_error, 100 * s.within_1_sigma, 100 * s.within_2_sigma,
        s.openings_found, s.true_openings, s.spurious_openings, s.median_opening_error);
    // Closed rooms, rooms with windows or angled walls, a scanner in a corner: every one measured.
    // Closets too: a door whose lintel is above the view is an opening, not the way out.
    if (s.category == "box" || s.category == "windows" || s.category == "angled" || s.category == "near_wall" ||
        s.category == "closet") {
      EXPECT_EQ(s.measured, s.rooms) << s.category;
    }
    if (s.category == "furniture") {
      EXPECT_GE(s.measured, 5u) << "furniture: a wardrobe under the ceiling is seen over, not a wall";
    }
    if (s.category == "doors") {
      EXPECT_GE(s.measured, 8u) << "doors: what is seen through a door is outside";
    }
    // Chimney breasts, alcoves, L and T rooms with one side turned away: that wall inferred.
    if (s.category == "chimney_breast") {
      EXPECT_GE(s.inferred, 4u) << "hidden sides inferred";
      EXPECT_EQ(s.wrong, 0u) << "a breast's front is a wall, not cut away";
    }
    if (s.category == "built_in") {
      EXPECT_EQ(s.wrong, 0u) << "a built-in's front seen past its end is not an L's inner wall";
    }
    if (s.category != "all") continue;
    EXPECT_GE(s.measured, 72u);
    EXPECT_GE(s.inferred, 8u);
    EXPECT_LE(s.wrong, 1u) << "rooms given status ok with walls that are not the room's";
    EXPECT_LT(s.median_wall_error, 0.006);
    // 59 of 81 measured (2026-12-05); 51 without each servo step's pitch error estimated.
    EXPECT_GE(s.within_target, 56u) << "rooms with every wall within 1 cm and the area within 0.5 %";
    EXPECT_LE(s.ok_over_2cm - s.wrong, 5u) << "rooms with the right walls, one of them more than 2 cm off";
    // The printed sigmas are calibrated: the true error within 1 sigma for 60-75 % of walls,
    // within 2 sigma for at least 93 %.
    EXPECT_GE(s.within_1_sigma, 0.60);
    EXPECT_LE(s.within_1_sigma, 0.75);
    EXPECT_GE(s.within_2_sigma, 0.93);
    // So are the corners' (one sigma of the distance from the true corner).
    EXPECT_GE(s.corners_within_1_sigma, 0.60);
    EXPECT_LE(s.corners_within_1_sigma, 0.75);
    EXPECT_GE(s.corners_within_2_sigma, 0.93);
    // Doors and windows on the measured walls: found (a door's header, a window's sill and
    // lintel do not hide them), their ends placed, nothing taken for one that is not.
    EXPECT_GE(s.openings_found, 0.9 * s.true_openings) << s.openings_found << " of " << s.true_openings;
    EXPECT_LE(s.spurious_openings, 1u);
    EXPECT_LT(s.median_opening_error, 0.015);
  }
  double worst_seen = 0;  // rooms whose every wall was seen (inferred rooms' walls hold only by their sigmas)
  for (const auto& c : cases)
    if (c.verdict == room_evaluation::Verdict::Measured) worst_seen = std::max(worst_seen, c.max_wall_error());
  EXPECT_LT(worst_seen, 0.035);
}
