// Thin DDS node: LaserScan in (rt/scan), optionally Imu (rt/imu) for the initial guess;
// one ScanMatch per scan out (rt/scan_match). Matching takes well under a millisecond, so
// it runs on the reader's listener thread, at the scan rate.
#include "scan_matcher_node.hpp"

#include <cmath>

#include "scanbus/clock.hpp"
#include "scanbus/geometry_message.hpp"
#include "scanbus/laser_scan_message.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/scan_matcher/imu_guess.hpp"
#include "scanbus/scan_matcher/pl_icp.hpp"

namespace scanbus::scan_matcher {

namespace {

// The message's own range_min..range_max (outside them a range is no return, as ROS defines
// it) travel with the scan: the matcher's gate applies them beside its own (sensor::kept_points).
std::optional<sensor::LaserScan> scan_of(const sensor_msgs::msg::LaserScan& message, std::string& problem) {
  if (!std::isfinite(message.angle_increment()) || message.angle_increment() == 0 ||
      !std::isfinite(message.angle_min())) {
    problem = "angle_min or angle_increment not usable";
    return std::nullopt;
  }
  return from_laser_scan_message(message);
}

scanbus::msg::Pose2D pose_message(const Pose2& pose) {
  scanbus::msg::Pose2D message;
  message.x(pose.x);
  message.y(pose.y);
  message.theta(pose.theta);
  return message;
}

class ScanMatcherService : public Service {
 public:
  explicit ScanMatcherService(ServiceContext& context)
      : log_(context.log),
        health_(context.health),
        matcher_(settings_of(context.config.section("scan_matcher"))),
        matches_(context.participant, topics::kScanMatch) {
    const Config config = context.config.section("scan_matcher");
    if (config.has("laser_axis_in_imu")) {
      const auto axis = config.numbers("laser_axis_in_imu", 3);
      laser_axis_ = Eigen::Vector3d(axis[0], axis[1], axis[2]);
      if (!(laser_axis_.norm() > 1e-6)) config.fail("laser_axis_in_imu", "must be a non-zero direction");
      laser_axis_.normalize();
    }
    if (config.flag("use_imu", false)) {
      imu_ = std::make_unique<Reader<sensor_msgs::msg::ImuPubSubType>>(
          context.participant, topics::kImu, [this](const auto& imu, const auto&) { receive(imu); });
    }
    scans_ = std::make_unique<Reader<sensor_msgs::msg::LaserScanPubSubType>>(
        context.participant, topics::kScan, [this](const auto& scan, const auto&) { receive(scan); });
  }

  int run() override {
    while (!StopSignal::requested()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    scans_.reset();  // no callback may outlive what it uses
    imu_.reset();
    return 0;
  }

 private:
  static MatcherSettings settings_of(const Config& section) {
    // Read here so an invalid file fails before any reader exists.
    section.flag("use_imu", false);
    return matcher_settings_from_config(section.section("matcher"));
  }

  void receive(const sensor_msgs::msg::Imu& imu) {
    const Eigen::Quaterniond orientation = to_eigen(imu.orientation());
    if (!orientation.coeffs().allFinite() || orientation.norm() < 0.5) {
      ++health_.counter("imu_rejected");
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    orientations_.add(to_seconds(imu.header().stamp()), orientation);
  }

  void receive(const sensor_msgs::msg::LaserScan& message) {
    std::string problem;
    const std::optional<sensor::LaserScan> scan = scan_of(message, problem);
    if (!scan) {
      health_.error("scan rejected: " + problem);
      ++health_.counter("scans_rejected");
      return;
    }
    const double stamp = to_seconds(message.header().stamp());
    std::lock_guard<std::mutex> lock(mutex_);
    const MatchResult result = matcher_.add_scan(*scan, imu_guess(stamp));
    previous_stamp_ = stamp;
    // The IMU guess's translation: the matched one, none after a failure (as the matcher holds)
    // or without constant velocity (as the matcher predicts).
    last_increment_ =
        result.quality == MatchQuality::Ok && matcher_.settings().constant_velocity ? result.increment : Pose2{};
    ++health_.counter(result.quality == MatchQuality::Ok || result.quality == MatchQuality::NoReference
                          ? "scans_matched"
                          : "matches_failed");
    if (result.quality != MatchQuality::Ok && result.quality != MatchQuality::NoReference)
      log_->warn(
          "match failed ({}): {} correspondences, {} explained; the pose follows the prediction once, then holds",
          static_cast<int>(result.quality), result.correspondences, result.inliers);
    matches_.write(to_message(result, message.header()));
  }

  // The IMU's turn since the previous scan with the previous translation, or none.
  std::optional<Pose2> imu_guess(double stamp) const {
    if (!imu_ || !previous_stamp_) return std::nullopt;
    const auto before = orientations_.at(*previous_stamp_), now = orientations_.at(stamp);
    if (!before || !now) return std::nullopt;
    return Pose2{last_increment_.x, last_increment_.y, rotation_about(*before, *now, laser_axis_)};
  }

  static scanbus::msg::ScanMatch to_message(const MatchResult& result, const std_msgs::msg::Header& header) {
    scanbus::msg::ScanMatch match;
    match.header(header);
    match.pose(pose_message(result.pose));
    match.increment(pose_message(result.increment));
    for (int row = 0; row < 3; ++row)
      for (int column = 0; column < 3; ++column) match.covariance()[row * 3 + column] = result.covariance(row, column);
    match.quality(static_cast<uint8_t>(result.quality));
    match.iterations(static_cast<uint32_t>(result.iterations));
    match.correspondences(static_cast<uint32_t>(result.correspondences));
    match.residual(result.residual);
    match.keyframe(result.keyframe);
    return match;
  }

  std::shared_ptr<spdlog::logger> log_;
  HealthReporter& health_;
  std::mutex mutex_;
  ScanMatcher matcher_;
  OrientationHistory orientations_;
  Eigen::Vector3d laser_axis_ = Eigen::Vector3d::UnitZ();
  std::optional<double> previous_stamp_;
  Pose2 last_increment_;
  Writer<scanbus::msg::ScanMatchPubSubType> matches_;
  std::unique_ptr<Reader<sensor_msgs::msg::ImuPubSubType>> imu_;
  std::unique_ptr<Reader<sensor_msgs::msg::LaserScanPubSubType>> scans_;
};

}  // namespace

std::unique_ptr<Service> make_scan_matcher(ServiceContext& context) {
  return std::make_unique<ScanMatcherService>(context);
}

}  // namespace scanbus::scan_matcher
