// room_measurement as a separate process: a whole-scan cloud in; a RoomMeasurement that a
// subscriber joining later still gets (TRANSIENT_LOCAL, depth 1), and the walls' inliers
// with a colour per wall.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <random>
#include <set>
#include <thread>

#include "scanbus/clock.hpp"
#include "scanbus/launch/system.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/service.hpp"
#include "scanbus/typed_topics.hpp"

using namespace scanbus;
using namespace std::chrono_literals;

namespace {

// Walls of a 5 m x 3.5 m room around the origin, floor to ceiling, 1 cm noise.
std::vector<CloudPoint> box_room() {
  std::mt19937 random(11);
  std::normal_distribution<float> noise(0, 0.01f);
  std::vector<CloudPoint> points;
  const Eigen::Vector2f corners[] = {{-2, -1.5f}, {3, -1.5f}, {3, 2}, {-2, 2}};
  for (int w = 0; w < 4; ++w) {
    const Eigen::Vector2f a = corners[w], b = corners[(w + 1) % 4];
    const Eigen::Vector2f normal = Eigen::Vector2f(-(b - a).y(), (b - a).x()).normalized();
    for (float t = 0; t <= 1; t += 0.006f)
      for (float z = -1.2f; z <= 1.3f; z += 0.05f) {
        const Eigen::Vector2f xy = a + t * (b - a) + noise(random) * normal;
        points.push_back({{xy.x(), xy.y(), z}, 100});
      }
  }
  return points;
}

template <class PubSubType>
std::optional<typename PubSubType::type> first_sample(Participant& participant, const Topic<PubSubType>& topic,
                                                      std::chrono::seconds timeout) {
  std::mutex mutex;
  std::optional<typename PubSubType::type> sample;
  Reader<PubSubType> reader(participant, topic, [&](const auto& s, const auto&) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!sample) sample = s;
  });
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (sample) return sample;
    }
    std::this_thread::sleep_for(50ms);
  }
  return std::nullopt;
}

}  // namespace

TEST(RoomService, MeasuresAScanAndLatchesTheResult) {
  char dir[] = "/tmp/scanbus_room_service_XXXXXX";
  const std::string work = mkdtemp(dir);
  launch::System system({SCANBUS_CLI, work, {"", "localhost", 83}, true});
  launch::ServiceConfig config;
  config.settings["scans"] = 1;
  ChildProcess& service = system.start("room_measurement", config);

  Participant participant(DdsSettings{"", "localhost", 83}, "scanbus/test_room");
  Writer<sensor_msgs::msg::PointCloud2PubSubType> scans(participant, topics::kScannerScanCloud);
  ASSERT_TRUE(scans.wait_for_readers(1, 20s));
  const builtin_interfaces::msg::Time scan_stamp = to_stamp(1.7e9 + 0.25);
  ASSERT_TRUE(scans.write(to_point_cloud2(box_room(), "scanner", scan_stamp)));
  const auto walls = first_sample(participant, topics::kRoomWalls, 30s);
  ASSERT_TRUE(walls.has_value());
  std::this_thread::sleep_for(500ms);

  // A subscriber that joins now, after the result went out.
  Participant late(DdsSettings{"", "localhost", 83}, "scanbus/test_room_late");
  const auto room = first_sample(late, topics::kRoomMeasurement, 10s);
  ASSERT_TRUE(room.has_value());
  EXPECT_EQ(room->status(), scanbus::msg::RoomMeasurement_Constants::OK) << room->message();
  // Stamped with the scan it was measured from, so a subscriber can pair them.
  EXPECT_EQ(room->header().stamp(), scan_stamp);
  EXPECT_EQ(walls->header().stamp(), scan_stamp);
  ASSERT_EQ(room->walls().size(), 4u);
  ASSERT_EQ(room->corners().size(), 4u);
  EXPECT_NEAR(room->floor_area(), 5.0 * 3.5, 0.02);
  for (const auto& wall : room->walls()) {
    EXPECT_TRUE(std::abs(wall.length() - 5.0) < 0.01 || std::abs(wall.length() - 3.5) < 0.01) << wall.length();
    EXPECT_NEAR(std::hypot(wall.plane()[0], wall.plane()[1]), 1.0, 1e-9);
    EXPECT_GT(wall.inliers(), 100u);
  }

  // The walls' inliers: x y z rgb, one colour per wall.
  ASSERT_EQ(walls->fields().size(), 4u);
  EXPECT_EQ(walls->fields()[3].name(), "rgb");
  std::set<uint32_t> colours;
  for (size_t i = 0; i < walls->width(); ++i) {
    uint32_t colour;
    std::memcpy(&colour, walls->data().data() + i * walls->point_step() + 12, 4);
    colours.insert(colour);
  }
  EXPECT_EQ(colours.size(), 4u);
  EXPECT_FALSE(service.exited().has_value());
}
