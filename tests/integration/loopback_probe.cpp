// A test service pair. `loopback_probe send` publishes a deterministic LaserScan, a
// PointCloud2 of N points, a RoomMeasurement and a TFMessage; `loopback_probe receive`
// regenerates the same samples, compares them byte for byte with what arrived, waits
// for the sender's Health, and exits 0 only when everything matched.
// `loopback_probe latch` writes the two latched samples (cloud, room) at once, with no
// reader yet, and stays (or streams the cloud for a while, lingers and exits, as a replay
// does); `loopback_probe receive-latched` is a late reader of both, as `scanbus cloud save`
// is of cloud_assembly's map.
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>

#include "scanbus/clock.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/service.hpp"
#include "scanbus/typed_topics.hpp"

namespace {

using namespace scanbus;
using namespace std::chrono_literals;

// splitmix64: a tiny deterministic generator both processes run identically.
uint64_t next_random(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

sensor_msgs::msg::PointCloud2 make_cloud(uint32_t points) {
  sensor_msgs::msg::PointCloud2 cloud;
  cloud.header().stamp(to_stamp(1700000000.25));
  cloud.header().frame_id("scanner");
  const char* names[] = {"x", "y", "z", "intensity"};
  for (uint32_t i = 0; i < 4; ++i) {
    sensor_msgs::msg::PointField field;
    field.name(names[i]);
    field.offset(4 * i);
    field.datatype(sensor_msgs::msg::PointField_Constants::FLOAT32);
    field.count(1);
    cloud.fields().push_back(field);
  }
  cloud.height(1);
  cloud.width(points);
  cloud.point_step(16);
  cloud.row_step(16 * points);
  cloud.is_dense(true);
  cloud.data().resize(size_t{16} * points);
  uint64_t state = 42;
  for (size_t i = 0; i < cloud.data().size(); i += 8) {
    const uint64_t word = next_random(state);
    std::memcpy(cloud.data().data() + i, &word, 8);
  }
  return cloud;
}

sensor_msgs::msg::LaserScan make_scan() {
  sensor_msgs::msg::LaserScan scan;
  scan.header().frame_id("laser");
  scan.header().stamp(to_stamp(1700000000.5));
  scan.angle_min(-2.356f);
  scan.angle_max(2.356f);
  scan.angle_increment(0.004363f);
  scan.range_min(0.1f);
  scan.range_max(30.0f);
  uint64_t state = 7;
  for (int i = 0; i < 1081; ++i) scan.ranges().push_back(static_cast<float>(next_random(state) % 30000) / 1000.0f);
  scan.ranges()[3] = std::numeric_limits<float>::infinity();
  scan.intensities().assign(1081, 100.0f);
  return scan;
}

scanbus::msg::RoomMeasurement make_room() {
  scanbus::msg::RoomMeasurement room;
  room.header().frame_id("scanner");
  for (int i = 0; i < 4; ++i) {
    scanbus::msg::Wall wall;
    wall.plane({1.0 * (i % 2), 1.0 * ((i + 1) % 2), 0.0, -2.0 - i});
    wall.length(4.0 + i);
    wall.inliers(1000 + i);
    room.walls().push_back(wall);
    geometry_msgs::msg::Point corner;
    corner.x(i);
    corner.y(-i);
    room.corners().push_back(corner);
  }
  room.floor_area(20.5);
  room.ceiling_height(std::nan(""));
  room.message("four walls");
  return room;
}

tf2_msgs::msg::TFMessage make_tf() {
  tf2_msgs::msg::TFMessage message;
  geometry_msgs::msg::TransformStamped transform;
  transform.header().frame_id("map");
  transform.child_frame_id("base_link");
  transform.transform().translation().z(12.5);
  transform.transform().rotation().w(1.0);
  message.transforms().push_back(transform);
  return message;
}

// Compares by serialised bytes: "intact" means exactly what the sender wrote.
template <class PubSubType>
bool same_bytes(const typename PubSubType::type& a, const typename PubSubType::type& b) {
  PubSubType type;
  const uint32_t size = type.getSerializedSizeProvider(const_cast<typename PubSubType::type*>(&a))();
  eprosima::fastrtps::rtps::SerializedPayload_t pa(size), pb(size + 64);
  if (!type.serialize(const_cast<typename PubSubType::type*>(&a), &pa)) return false;
  if (!type.serialize(const_cast<typename PubSubType::type*>(&b), &pb)) return false;
  return pa.length == pb.length && std::memcmp(pa.data, pb.data, pa.length) == 0;
}

class Sender : public Service {
 public:
  Sender(ServiceContext& context, bool latched_only)
      : log_(context.log),
        latched_only_(latched_only),
        points_(static_cast<uint32_t>(context.config.section("probe").integer("points", 1000000, 1, 10000000))),
        rewrite_period_(context.config.section("probe").number("rewrite_period", 0.0, 0.0, 60.0)),
        stream_for_(context.config.section("probe").number("stream_for", 0.0, 0.0, 600.0)),
        linger_(context.config.section("probe").number("linger", 0.0, 0.0, 600.0)),
        scan_(context.participant, topics::kScan, QosSettings{true, false, false, 10}),
        cloud_(context.participant, topics::kScannerCloud),
        room_(context.participant, topics::kRoomMeasurement),
        tf_(context.participant, topics::kTf),
        sent_(context.health.counter("samples_sent")) {}

  int run() override { return latched_only_ ? latch() : send(); }

 private:
  int latch() {
    const auto cloud = make_cloud(points_);
    const bool written = cloud_.write(cloud) && room_.write(make_room());
    sent_ += 2;
    log_->info("latched 2 samples, cloud of {} points ({} bytes)", points_, cloud.data().size());
    if (!written) return 1;
    // As cloud_assembly does while its map grows: the same cloud again every period; with
    // stream_for, for that long, then (as a replay at its end) linger and exit.
    const auto period = std::chrono::milliseconds(std::max(10L, static_cast<long>(rewrite_period_ * 1000)));
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(stream_for_);
    while (!StopSignal::wait_for(rewrite_period_ > 0 ? period : std::chrono::milliseconds(1000))) {
      if (stream_for_ > 0 && std::chrono::steady_clock::now() > end) {
        log_->info("stream ended; lingering {} s", linger_);
        linger_for_lagging_readers(linger_);
        return 0;
      }
      if (rewrite_period_ > 0 && !cloud_.write(cloud)) log_->warn("cloud not written again");
    }
    return 0;
  }

  int send() {
    if (!scan_.wait_for_readers(1, 30s) || !cloud_.wait_for_readers(1, 30s) || !room_.wait_for_readers(1, 30s) ||
        !tf_.wait_for_readers(1, 30s)) {
      log_->error("no receiver matched within 30 s");
      return 1;
    }
    const auto cloud = make_cloud(points_);
    const bool written =
        scan_.write(make_scan()) && cloud_.write(cloud) && room_.write(make_room()) && tf_.write(make_tf());
    sent_ += 4;
    log_->info("wrote 4 samples, cloud of {} points ({} bytes)", points_, cloud.data().size());
    if (!written) return 1;
    while (!StopSignal::wait_for(1s)) {
    }
    return 0;
  }

  std::shared_ptr<spdlog::logger> log_;
  bool latched_only_;
  uint32_t points_;
  double rewrite_period_;  // latch: the cloud written again this often (s), 0 once
  double stream_for_;      // latch: s of that, then linger_ s and exit; 0 until stopped
  double linger_;
  Writer<sensor_msgs::msg::LaserScanPubSubType> scan_;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> cloud_;
  Writer<scanbus::msg::RoomMeasurementPubSubType> room_;
  Writer<tf2_msgs::msg::TFMessagePubSubType> tf_;
  std::atomic<uint64_t>& sent_;
};

class Receiver : public Service {
 public:
  Receiver(ServiceContext& context, size_t expected_kinds)
      : log_(context.log),
        expected_kinds_(expected_kinds),
        points_(static_cast<uint32_t>(context.config.section("probe").integer("points", 1000000, 1, 10000000))),
        timeout_(context.config.section("probe").number("timeout", 60.0, 1.0, 600.0)),
        scan_(context.participant, topics::kScan, QosSettings{true, false, false, 10},
              [this](const auto& s, const auto&) {
                check("LaserScan", same_bytes<sensor_msgs::msg::LaserScanPubSubType>(s, make_scan()));
              }),
        cloud_(context.participant, topics::kScannerCloud,
               [this](const auto& s, const auto&) {
                 check("PointCloud2", same_bytes<sensor_msgs::msg::PointCloud2PubSubType>(s, make_cloud(points_)));
               }),
        room_(context.participant, topics::kRoomMeasurement,
              [this](const auto& s, const auto&) {
                check("RoomMeasurement", same_bytes<scanbus::msg::RoomMeasurementPubSubType>(s, make_room()));
              }),
        tf_(context.participant, topics::kTf,
            [this](const auto& s, const auto&) {
              check("TFMessage", same_bytes<tf2_msgs::msg::TFMessagePubSubType>(s, make_tf()));
            }),
        health_(context.participant, topics::kHealth, [this](const auto& s, const auto&) {
          if (s.service() == "probe_sender") check("Health", true);
        }) {}

  int run() override {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_);
    while (!StopSignal::wait_for(100ms)) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!failed_.empty()) break;
      if (passed_.size() == expected_kinds_) break;
      if (std::chrono::steady_clock::now() > deadline) break;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& name : passed_) std::cout << "intact: " << name << "\n";
    for (const auto& name : failed_) std::cout << "CORRUPT: " << name << "\n";
    if (passed_.size() == expected_kinds_ && failed_.empty()) return 0;
    std::cout << "received " << passed_.size() << " of " << expected_kinds_ << " expected kinds\n";
    return 1;
  }

 private:
  void check(const std::string& name, bool ok) {
    std::lock_guard<std::mutex> lock(mutex_);
    (ok ? passed_ : failed_).insert(name);
  }

  std::shared_ptr<spdlog::logger> log_;
  size_t expected_kinds_;  // all five, or the latched two and Health
  uint32_t points_;
  double timeout_;
  std::mutex mutex_;
  std::set<std::string> passed_, failed_;
  Reader<sensor_msgs::msg::LaserScanPubSubType> scan_;
  Reader<sensor_msgs::msg::PointCloud2PubSubType> cloud_;
  Reader<scanbus::msg::RoomMeasurementPubSubType> room_;
  Reader<tf2_msgs::msg::TFMessagePubSubType> tf_;
  Reader<scanbus::msg::HealthPubSubType> health_;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  const bool latched = mode == "latch" || mode == "receive-latched";
  if (mode == "send" || mode == "latch")
    return service_main("probe_sender", argc - 1, argv + 1,
                        [latched](ServiceContext& c) { return std::make_unique<Sender>(c, latched); });
  if (mode == "receive" || mode == "receive-latched")
    return service_main("probe_receiver", argc - 1, argv + 1,
                        [latched](ServiceContext& c) { return std::make_unique<Receiver>(c, latched ? 3 : 5); });
  std::cerr << "usage: loopback_probe send|receive|latch|receive-latched [--config FILE]\n";
  return 2;
}
