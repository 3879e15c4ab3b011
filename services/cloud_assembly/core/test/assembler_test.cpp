#include <gtest/gtest.h>

#include "scanbus/cloud_assembly/assembler.hpp"

using namespace scanbus::cloud_assembly;

namespace {

// A downward scan of three rays 1 m long, stamped `stamp`.
scanbus::sensor::LaserScan scan_at(double stamp) { return {stamp, -0.1f, 0.1f, 0.05f, 30.0f, {1.0f, 1.0f, 1.0f}}; }

Eigen::Isometry3d up(double z) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation().z() = z;
  return t;
}

AssemblerSettings settings() {
  AssemblerSettings s;
  s.gating.opening = M_PI;
  return s;
}

}  // namespace

TEST(Assembler, AScanWaitsForItsTransformThenJoinsTheCloudAndTheWindow) {
  Assembler assembler(settings());
  assembler.add_static("base_link", "laser", up(-0.1));
  AssemblyReport report = assembler.add_scan("laser", scan_at(10.0), 0);
  EXPECT_EQ(report.assembled, 0u) << "no map -> base_link at 10 s yet";
  EXPECT_DOUBLE_EQ(assembler.newest_assembled(), 0.0);
  assembler.add_transform("map", "base_link", 9.9, up(2.0));
  assembler.add_transform("map", "base_link", 10.1, up(2.2));
  report = assembler.assemble_ready(0);
  EXPECT_EQ(report.assembled, 1u);
  EXPECT_TRUE(report.problems.empty());
  const WindowReply window = assembler.window(9.0, 11.0, "");
  ASSERT_EQ(window.status, WindowReply::Ok);
  ASSERT_EQ(window.points.size(), 3u);
  for (const auto& p : window.points) EXPECT_NEAR(p.z(), 2.1 - 0.1, 1e-5) << "the transform at 10 s, interpolated";
  EXPECT_EQ(assembler.continuous().size(), 3u);
  EXPECT_DOUBLE_EQ(assembler.newest_stamp(), 10.1);
  EXPECT_DOUBLE_EQ(assembler.newest_assembled(), 10.0);  // the cloud's stamp: the scan's, not the transform's
}

TEST(Assembler, AScanStillWithoutItsTransformAfterTheTimeoutIsDroppedWithTheReason) {
  Assembler assembler(settings());  // transform_timeout 2 s
  assembler.add_static("map", "odom", up(0));
  assembler.add_transform("odom", "laser", 0.5, up(1));
  EXPECT_EQ(assembler.add_scan("laser", scan_at(1.0), 0).assembled, 0u);  // after the last transform: waits
  EXPECT_EQ(assembler.add_scan("laser", scan_at(2.0), 0).dropped, 0u);
  const AssemblyReport report = assembler.add_scan("laser", scan_at(3.5), 0);  // 2.5 s past the first
  EXPECT_EQ(report.dropped, 1u);
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_EQ(report.problems[0].rfind("scan dropped: ", 0), 0u) << report.problems[0];
  EXPECT_FALSE(report.frames_missing) << "the frames are joined, only not at that time";
}

TEST(Assembler, FramesNoTransformJoinsAreSaidOnceAfterASecond) {
  Assembler assembler(settings());
  EXPECT_FALSE(assembler.add_scan("laser", scan_at(1.0), 100.0).frames_missing);
  EXPECT_FALSE(assembler.add_scan("laser", scan_at(1.1), 100.5).frames_missing) << "normal for a moment after a start";
  const AssemblyReport said = assembler.add_scan("laser", scan_at(1.2), 101.1);
  EXPECT_TRUE(said.frames_missing);
  ASSERT_EQ(said.problems.size(), 1u);
  EXPECT_NE(said.problems[0].find("no transform has joined 'laser' to 'map'"), std::string::npos) << said.problems[0];
  EXPECT_FALSE(assembler.add_scan("laser", scan_at(1.3), 102.0).frames_missing) << "said once";
  assembler.add_static("map", "laser", up(0));
  const AssemblyReport joined = assembler.assemble_ready(102.5);
  EXPECT_EQ(joined.assembled, 4u) << "every waiting scan, once the frames are joined";
}

// A message of several transforms (as tf publishers send) is taken whole before the waiting
// scans are looked at: its newer stamps must not time a scan out that its other transforms
// complete.
TEST(Assembler, AMessagesTransformsAreAllInBeforeAnyScanIsTimedOut) {
  Assembler assembler(settings());  // transform_timeout 2 s; map -> odom and odom -> base_link 5 s apart
  assembler.add_static("base_link", "laser", up(0));
  assembler.add_scan("laser", scan_at(1.0), 0);  // waits: nothing joins map and base_link yet
  assembler.add_transform("map", "odom", 0.0, up(0));
  assembler.add_transform("map", "odom", 5.0, up(0));        // 4 s newer than the scan
  assembler.add_transform("odom", "base_link", 0.0, up(1));  // the message's last two complete the chain
  assembler.add_transform("odom", "base_link", 0.5, up(1));  // (the body's pose within max_pose_gap)
  assembler.add_transform("odom", "base_link", 1.2, up(1));
  assembler.add_transform("odom", "base_link", 5.0, up(1));
  const AssemblyReport report = assembler.assemble_ready(0);
  EXPECT_EQ(report.assembled, 1u);
  EXPECT_EQ(report.dropped, 0u) << (report.problems.empty() ? "" : report.problems[0]);
}

// The pose source restarted: its poses stop at 0.5 s and come again from 3 s. A scan in
// between is dropped at once, with the gap named, not placed on the line between the two and
// not held up to the timeout either; the scans on both sides are placed.
TEST(Assembler, AScanInAGapOfThePosesIsDroppedAtOnce) {
  Assembler assembler(settings());  // max_pose_gap 1 s
  assembler.add_static("base_link", "laser", up(0));
  for (double t = 0; t <= 0.5; t += 0.1) assembler.add_transform("map", "base_link", t, up(1));
  for (double t = 3.0; t <= 3.2; t += 0.1) assembler.add_transform("map", "base_link", t, up(1.3));
  EXPECT_EQ(assembler.add_scan("laser", scan_at(0.45), 0).assembled, 1u);
  const AssemblyReport gap = assembler.add_scan("laser", scan_at(1.5), 0);
  EXPECT_EQ(gap.dropped, 1u);
  ASSERT_EQ(gap.problems.size(), 1u);
  EXPECT_NE(gap.problems[0].find("falls in a gap of 2.500 s"), std::string::npos) << gap.problems[0];
  EXPECT_EQ(assembler.add_scan("laser", scan_at(3.05), 0).assembled, 1u);
}

TEST(Assembler, WindowRequestsThatCannotBeAnsweredSayWhy) {
  Assembler assembler(settings());
  assembler.add_static("map", "laser", up(1));
  assembler.add_scan("laser", scan_at(5.0), 0);
  EXPECT_EQ(assembler.window(6.0, 5.0, "").status, WindowReply::BadRequest);
  const WindowReply elsewhere = assembler.window(4.0, 6.0, "base_link");
  EXPECT_EQ(elsewhere.status, WindowReply::BadRequest);
  EXPECT_NE(elsewhere.message.find("no transform to 'base_link'"), std::string::npos) << elsewhere.message;
  const WindowReply empty = assembler.window(7.0, 8.0, "");
  EXPECT_EQ(empty.status, WindowReply::Empty);
  EXPECT_NE(empty.message.find("kept: 5.0"), std::string::npos) << empty.message;
  const WindowReply in_laser = assembler.window(4.0, 6.0, "laser");  // back into the scan's own frame
  ASSERT_EQ(in_laser.status, WindowReply::Ok);
  for (const auto& p : in_laser.points) EXPECT_NEAR(p.norm(), 1.0, 1e-5);
}
