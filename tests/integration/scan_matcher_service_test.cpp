// scan_matcher as a separate process: LaserScans of a known flight in (rt/scan), one
// ScanMatch per scan out (rt/scan_match) tracking the true motion; a malformed scan is
// rejected (Health counts it) without losing the pose.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <thread>

#include "laser_world.hpp"
#include "scanbus/child_process.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/dds.hpp"
#include "scanbus/messages.hpp"

using namespace scanbus;
using namespace std::chrono_literals;
using scan_matcher::Pose2;

namespace {

sensor_msgs::msg::LaserScan laser_scan(const scan_matcher::Scan& scan, double stamp) {
  sensor_msgs::msg::LaserScan message;
  message.header().stamp(to_stamp(stamp));
  message.header().frame_id("laser");
  message.angle_min(static_cast<float>(scan.angle_min));
  message.angle_increment(static_cast<float>(scan.angle_increment));
  message.angle_max(static_cast<float>(scan.angle_min + scan.angle_increment * (scan.ranges.size() - 1)));
  message.range_min(0.05f);
  message.range_max(30.0f);
  message.ranges(scan.ranges);
  return message;
}

}  // namespace

TEST(ScanMatcherService, TracksAKnownFlightAndRejectsABadScan) {
  setenv("SCANBUS_DOMAIN_ID", "82", 1);
  char dir[] = "/tmp/scanbus_scan_matcher_XXXXXX";
  const std::string work = mkdtemp(dir);
  // Reliable on rt/scan so this test loses nothing by design (the catalogue's best effort
  // is what a sensor stream wants).
  std::ofstream(work + "/matcher.yaml") << "qos:\n  rt/scan: {reliability: reliable, depth: 100}\n";
  ChildProcess service(SCANBUS_CLI, {"run", "scan_matcher", "--config", work + "/matcher.yaml"}, work + "/matcher.log");

  Participant participant(DdsSettings{"", "localhost", 82}, "scanbus/test_scan_matcher");
  QosSettings reliable;
  reliable.depth = 100;
  Writer<sensor_msgs::msg::LaserScanPubSubType> scans(participant, "rt/scan", reliable);
  std::mutex mutex;
  std::vector<scanbus::msg::ScanMatch> matches;
  Reader<scanbus::msg::ScanMatchPubSubType> reader(participant, "rt/scan_match", [&](const auto& match, const auto&) {
    std::lock_guard<std::mutex> lock(mutex);
    matches.push_back(match);
  });
  std::atomic<uint64_t> rejected{0};
  Reader<scanbus::msg::HealthPubSubType> health(participant, "rt/scanbus/health", [&](const auto& h, const auto&) {
    if (h.service() != "scan_matcher") return;
    for (const auto& counter : h.counters())
      if (counter.name() == "scans_rejected") rejected = counter.value();
  });
  ASSERT_TRUE(scans.wait_for_readers(1, 20s));
  for (int i = 0; i < 200 && reader.matched_writers() == 0; ++i) std::this_thread::sleep_for(100ms);
  ASSERT_EQ(reader.matched_writers(), 1u);

  const auto room = test_support::LaserWorld::room();
  std::mt19937 random(5);
  const Pose2 start{-1.5, -0.5, 0.2}, step{0.05, 0.01, 1.5 * M_PI / 180};
  Pose2 truth = start;
  constexpr int kScans = 30;
  for (int i = 0; i < kScans; ++i) {
    ASSERT_TRUE(scans.write(laser_scan(room.scan(truth, {}, random), 100.0 + 0.1 * i)));
    if (i == 10) {  // a scan no matcher can use: no angle increment
      auto broken = laser_scan(room.scan(truth, {}, random), 100.0 + 0.1 * i + 0.05);
      broken.angle_increment(0);
      ASSERT_TRUE(scans.write(broken));
    }
    truth = truth * step;
  }
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (matches.size() >= kScans && rejected.load() == 1) break;
    }
    std::this_thread::sleep_for(50ms);
  }
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(matches.size(), static_cast<size_t>(kScans)) << "one ScanMatch per usable scan";
  EXPECT_EQ(rejected.load(), 1u);
  EXPECT_EQ(matches.front().quality(), scanbus::msg::ScanMatch_Constants::NO_REFERENCE);
  const Pose2 travelled = start.inverse() * (truth * step.inverse());
  const auto& last = matches.back();
  EXPECT_EQ(last.quality(), scanbus::msg::ScanMatch_Constants::OK);
  EXPECT_NEAR(last.pose().x(), travelled.x, 0.03);
  EXPECT_NEAR(last.pose().y(), travelled.y, 0.03);
  EXPECT_NEAR(last.pose().theta(), travelled.theta, 0.5 * M_PI / 180);
  EXPECT_NEAR(last.increment().x(), step.x, 0.01);
  EXPECT_NEAR(to_seconds(last.header().stamp()), 100.0 + 0.1 * (kScans - 1), 1e-6);
  EXPECT_EQ(last.header().frame_id(), "laser");
  EXPECT_GT(last.covariance()[0], 0);
  EXPECT_GT(last.correspondences(), 100u);
}
