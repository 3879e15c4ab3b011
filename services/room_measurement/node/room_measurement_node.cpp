// Thin DDS node: whole scans in (rt/scanner/scan_cloud); after `scans` of them, the room's
// RoomMeasurement and its walls' inliers coloured per wall out, stamped with the last scan
// they were measured from (so a subscriber can tell which scan a room came from). Measuring
// runs on the service's thread, not on the DDS listener's.
#include "room_measurement_node.hpp"

#include <condition_variable>
#include <cstring>

#include "scanbus/messages.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/room_measurement/room_measurement.hpp"
#include "scanbus/room_measurement/room_message.hpp"

namespace scanbus::room_measurement {

namespace {

class RoomMeasurementService : public Service {
 public:
  explicit RoomMeasurementService(ServiceContext& context)
      : log_(context.log),
        health_(context.health),
        measurement_(context.participant, topics::kRoomMeasurement),
        walls_(context.participant, topics::kRoomWalls),
        scans_(context.participant, topics::kScannerScanCloud,
               [this](const auto& cloud, const auto&) { receive(cloud); }) {
    const RoomServiceSettings settings = room_service_settings(context.config.section("room_measurement"));
    scans_needed_ = settings.scans;
    frame_id_ = settings.frame_id;
    settings_ = settings.room;
  }

  int run() override {
    while (!StopSignal::requested()) {
      std::vector<Eigen::Vector3f> points;
      builtin_interfaces::msg::Time stamp;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        ready_.wait_for(lock, std::chrono::milliseconds(200), [this] { return scans_held_ >= scans_needed_; });
        if (scans_held_ < scans_needed_) continue;
        points.swap(points_);
        stamp = newest_stamp_;
        scans_held_ = 0;
      }
      measure(points, stamp);
    }
    return 0;
  }

 private:
  void receive(const sensor_msgs::msg::PointCloud2& cloud) {
    std::vector<CloudPoint> points;
    try {
      points = from_point_cloud2(cloud);
    } catch (const std::invalid_argument& e) {
      health_.error(std::string("scan cloud rejected: ") + e.what());
      ++health_.counter("clouds_rejected");
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& point : points) points_.push_back(point.position);
    newest_stamp_ = cloud.header().stamp();
    ++scans_held_;
    ++health_.counter("scans_received");
    if (scans_held_ >= scans_needed_) ready_.notify_one();
  }

  void measure(const std::vector<Eigen::Vector3f>& points, const builtin_interfaces::msg::Time& stamp) {
    const RoomResult result = measure_room(points, settings_);
    log_->info("{} from {} points in {:.1f} ms: {}", status_name(result.status), result.points_in, result.elapsed_ms,
               result.message);
    ++health_.counter(result.status == RoomStatus::Ok ? "rooms_measured" : "rooms_not_measured");
    measurement_.write(to_message(result, frame_id_, stamp));
    walls_.write(walls_cloud(result, frame_id_, stamp));
  }

  std::shared_ptr<spdlog::logger> log_;
  HealthReporter& health_;
  Writer<scanbus::msg::RoomMeasurementPubSubType> measurement_;
  Writer<sensor_msgs::msg::PointCloud2PubSubType> walls_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::vector<Eigen::Vector3f> points_;
  builtin_interfaces::msg::Time newest_stamp_;
  size_t scans_held_ = 0;
  size_t scans_needed_ = 3;
  std::string frame_id_;
  RoomSettings settings_;
  Reader<sensor_msgs::msg::PointCloud2PubSubType> scans_;  // last: callbacks need everything above
};

}  // namespace

RoomServiceSettings room_service_settings(const Config& section) {
  RoomServiceSettings settings;
  settings.scans = static_cast<size_t>(section.integer("scans", 3, 1, 100));
  settings.frame_id = section.text("frame_id", "scanner");
  settings.room = room_settings_from_config(section);
  return settings;
}

RoomSettings room_settings_from_file(const std::string& path) {
  const Config section = Config::load(path).section("room_measurement");
  const RoomSettings settings = room_service_settings(section).room;
  section.check_all_read();
  return settings;
}

std::unique_ptr<Service> make_room_measurement(ServiceContext& context) {
  return std::make_unique<RoomMeasurementService>(context);
}

}  // namespace scanbus::room_measurement
