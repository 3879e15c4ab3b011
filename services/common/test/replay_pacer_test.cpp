#include <gtest/gtest.h>

#include <cmath>

#include "scanbus/replay_pacer.hpp"

using scanbus::ReplayPacer;

TEST(ReplayPacer, RegularStampsAreDueAtTheirPace) {
  ReplayPacer pacer(2.0, 60);
  EXPECT_DOUBLE_EQ(pacer.next(100).due, 0);
  EXPECT_DOUBLE_EQ(pacer.next(101).due, 0.5);
  EXPECT_DOUBLE_EQ(pacer.next(100.5).due, 0.25);  // a little out of order: goes when due (at once)
  EXPECT_DOUBLE_EQ(pacer.next(110).due, 5);
  EXPECT_FALSE(pacer.finish());
  EXPECT_EQ(pacer.skipped(), 0u);
}

// One stamp 1e10 s ahead (about where int64 nanoseconds overflow) is skipped; the replay
// neither waits for it nor loses its pace.
TEST(ReplayPacer, ALoneStampFarAheadIsSkipped) {
  ReplayPacer pacer(1.0, 60);
  pacer.next(0);
  pacer.next(1);
  const auto jump = pacer.next(1e10);
  EXPECT_TRUE(jump.hold);
  const auto after = pacer.next(2);
  EXPECT_TRUE(after.skip_held);
  EXPECT_FALSE(after.publish_held);
  EXPECT_DOUBLE_EQ(after.due, 2);
  EXPECT_EQ(pacer.skipped(), 1u);
}

TEST(ReplayPacer, StampsGoingFarBackOrNotANumberAreSkipped) {
  ReplayPacer pacer(1.0, 60);
  pacer.next(1000);
  EXPECT_TRUE(pacer.next(-1e12).hold);
  EXPECT_TRUE(pacer.next(NAN).hold);  // the far one skipped, this one held
  const auto after = pacer.next(1001);
  EXPECT_TRUE(after.skip_held);
  EXPECT_DOUBLE_EQ(after.due, 1);
  EXPECT_EQ(pacer.skipped(), 2u);
}

TEST(ReplayPacer, ALoneStampAtTheEndIsSkipped) {
  ReplayPacer pacer(1.0, 60);
  pacer.next(0);
  EXPECT_TRUE(pacer.next(1e300).hold);
  EXPECT_TRUE(pacer.finish());
  EXPECT_EQ(pacer.skipped(), 1u);
}

// A recording paused for an hour: nothing is lost, the hour is not waited.
TEST(ReplayPacer, APauseIsTakenUpAtOnce) {
  ReplayPacer pacer(1.0, 60);
  pacer.next(0);
  pacer.next(5);
  EXPECT_TRUE(pacer.next(3605).hold);
  const auto after = pacer.next(3606);
  EXPECT_TRUE(after.publish_held);
  EXPECT_FALSE(after.skip_held);
  EXPECT_DOUBLE_EQ(after.due, 6);
  EXPECT_DOUBLE_EQ(pacer.next(3610).due, 10);
  EXPECT_EQ(pacer.pauses(), 1u);
  EXPECT_EQ(pacer.skipped(), 0u);
}
