#include <gtest/gtest.h>

#include "scanbus/scanner_io/device_watchdog.hpp"

using scanbus::scanner_io::DeviceWatchdog;

TEST(DeviceWatchdog, SilenceIsAStallOnlyWhileLinesAreDue) {
  DeviceWatchdog watchdog(2.0, 0.2, 5.0);
  watchdog.expect(false, 0);
  EXPECT_FALSE(watchdog.stalled(100));  // an idle device may say nothing for ever
  watchdog.expect(true, 100);           // START sent
  EXPECT_FALSE(watchdog.stalled(101.9));
  watchdog.line(101.9);
  EXPECT_FALSE(watchdog.stalled(103.8));
  EXPECT_TRUE(watchdog.stalled(104));
  EXPECT_NEAR(watchdog.silent_for(104), 2.1, 1e-9);
  watchdog.expect(false, 104);  // the scan ended (DONE)
  EXPECT_FALSE(watchdog.stalled(200));
}

TEST(DeviceWatchdog, ResetsBackOffUntilALineComes) {
  DeviceWatchdog watchdog(1.0, 0.2, 1.0);
  watchdog.expect(true, 0);
  ASSERT_TRUE(watchdog.stalled(1.5));
  EXPECT_DOUBLE_EQ(watchdog.reset(), 0.2);
  EXPECT_FALSE(watchdog.stalled(10));  // nothing due until the reopened session asks
  watchdog.expect(true, 10);
  ASSERT_TRUE(watchdog.stalled(11.5));
  EXPECT_DOUBLE_EQ(watchdog.reset(), 0.4);
  EXPECT_DOUBLE_EQ(watchdog.reset(), 0.8);
  EXPECT_DOUBLE_EQ(watchdog.reset(), 1.0);  // at most reconnect_max
  watchdog.line(20);
  EXPECT_DOUBLE_EQ(watchdog.reset(), 0.2);  // the device spoke: from the start again
}
