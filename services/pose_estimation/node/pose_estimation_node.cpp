// Thin DDS node around the PoseEstimator: every input goes in under one lock, every pose
// that becomes ready goes out as PoseWithCovarianceStamped and as the base_link transform,
// and again on rt/pose/settled when its height leaves the fusion's window.
#include "pose_estimation_node.hpp"

#include <cmath>

#include "scanbus/clock.hpp"
#include "scanbus/geometry_message.hpp"
#include "scanbus/laser_scan_message.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/pose_estimation/pose_estimator.hpp"

namespace scanbus::pose_estimation {

namespace {

struct Frames {
  std::string map, body, laser;
};

Frames read_frames(const Config& section) {
  const Config frames = section.section("frames");
  return {frames.text("map", "map"), frames.text("base_link", "base_link"), frames.text("laser", "laser")};
}

geometry_msgs::msg::TransformStamped transform_message(double stamp, const std::string& parent,
                                                       const std::string& child, const Eigen::Isometry3d& t) {
  geometry_msgs::msg::TransformStamped message;
  message.header().stamp(to_stamp(stamp));
  message.header().frame_id(parent);
  message.child_frame_id(child);
  message.transform(to_transform_message(t));
  return message;
}

class PoseEstimation : public Service {
 public:
  explicit PoseEstimation(ServiceContext& context)
      : log_(context.log),
        health_(context.health),
        settings_(pose_estimator_settings_from_config(context.config.section("pose_estimation"))),
        frames_(read_frames(context.config.section("pose_estimation"))),
        input_ended_after_(context.config.section("pose_estimation").number("input_ended_after", 5.0, 0.05, 3600.0)),
        estimator_(settings_),
        poses_(context.participant, topics::kPose),
        settled_poses_(context.participant, topics::kPoseSettled),
        tf_(context.participant, topics::kTf),
        tf_static_(context.participant, topics::kTfStatic) {
    mount_.transforms().push_back(
        transform_message(to_seconds(now_stamp()), frames_.body, frames_.laser, settings_.laser_in_body));
    tf_static_.write(mount_);  // transient local: late subscribers get it too
    imu_ = std::make_unique<Reader<sensor_msgs::msg::ImuPubSubType>>(
        context.participant, topics::kImu, [this](const auto& m, const auto&) { receive(m); });
    fixes_ = std::make_unique<Reader<sensor_msgs::msg::NavSatFixPubSubType>>(
        context.participant, topics::kFix, [this](const auto& m, const auto&) { receive(m); });
    pressures_ = std::make_unique<Reader<sensor_msgs::msg::FluidPressurePubSubType>>(
        context.participant, topics::kPressure, [this](const auto& m, const auto&) { receive(m); });
    matches_ = std::make_unique<Reader<scanbus::msg::ScanMatchPubSubType>>(
        context.participant, topics::kScanMatch, [this](const auto& m, const auto&) { receive(m); });
    if (settings_.ground_clearance)
      scans_ = std::make_unique<Reader<sensor_msgs::msg::LaserScanPubSubType>>(
          context.participant, topics::kScan, [this](const auto& m, const auto&) { receive(m); });
  }

  // Every 100 ms: the mount to readers that joined since, and, when no sample has come for
  // input_ended_after s of wall time (a replay's end, every sensor silent), the results
  // still waiting for newer data.
  int run() override {
    while (!StopSignal::requested()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      std::lock_guard<std::mutex> lock(mutex_);
      republish_mount_to_new_readers();
      if (std::chrono::steady_clock::now() - last_input_ > std::chrono::duration<double>(input_ended_after_))
        publish_ready(true);  // counted as poses_after_input_ended
    }
    scans_.reset();  // no callback may outlive what it uses
    matches_.reset();
    pressures_.reset();
    fixes_.reset();
    imu_.reset();
    {
      // Stopped: the poses still waiting and those still in the window go out now, or the
      // cloud would lose the flight's last seconds.
      std::lock_guard<std::mutex> lock(mutex_);
      publish_ready(true);
    }
    settled_poses_.wait_for_acknowledgments(std::chrono::seconds(2));
    return 0;
  }

 private:
  void receive(const sensor_msgs::msg::Imu& imu) {
    const Eigen::Quaterniond orientation = to_eigen(imu.orientation());
    if (!orientation.coeffs().allFinite() || std::abs(orientation.norm() - 1) > 0.01) {
      reject("imu_rejected", "IMU orientation is not a unit quaternion");
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    estimator_.add_imu(to_seconds(imu.header().stamp()), orientation);
    publish_ready();
  }

  void receive(const sensor_msgs::msg::NavSatFix& fix) {
    if (fix.status().status() < sensor_msgs::msg::NavSatStatus_Constants::STATUS_FIX ||
        !std::isfinite(fix.latitude()) || !std::isfinite(fix.longitude()) || !std::isfinite(fix.altitude())) {
      reject("fixes_rejected", "GPS fix without a position");
      return;
    }
    // Diagonal sigmas from the covariance; an unknown one counts as 10 m.
    const bool known = fix.position_covariance_type() != sensor_msgs::msg::NavSatFix_Constants::COVARIANCE_TYPE_UNKNOWN;
    const double horizontal = known ? std::sqrt(std::max(fix.position_covariance()[0], 0.0)) : 10.0;
    const double vertical = known ? std::sqrt(std::max(fix.position_covariance()[8], 0.0)) : 10.0;
    std::lock_guard<std::mutex> lock(mutex_);
    estimator_.add_fix(to_seconds(fix.header().stamp()), fix.latitude(), fix.longitude(), fix.altitude(), horizontal,
                       vertical);
    publish_ready();
  }

  void receive(const sensor_msgs::msg::FluidPressure& pressure) {
    if (!(pressure.fluid_pressure() > 1000 && pressure.fluid_pressure() < 200000)) {
      reject("pressures_rejected", "pressure outside 1 to 200 kPa");
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    estimator_.add_pressure(to_seconds(pressure.header().stamp()), pressure.fluid_pressure());
    publish_ready();
  }

  void receive(const scanbus::msg::ScanMatch& match) {
    std::optional<Eigen::Vector2d> increment;
    if (match.quality() == scanbus::msg::ScanMatch_Constants::OK)
      increment = Eigen::Vector2d(match.increment().x(), match.increment().y());
    std::lock_guard<std::mutex> lock(mutex_);
    estimator_.add_match(to_seconds(match.header().stamp()), increment);
    publish_ready();
  }

  void receive(const sensor_msgs::msg::LaserScan& scan) {
    if (!std::isfinite(scan.angle_min()) || !std::isfinite(scan.angle_increment()) || scan.angle_increment() == 0) {
      reject("scans_rejected", "LaserScan angle_min or angle_increment not usable");
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    estimator_.add_scan(from_laser_scan_message(scan));
    publish_ready();
  }

  // The mount again whenever a reader joined: Fast DDS 2.9 now and then never delivers a
  // transient-local sample to a late-joining reader (eProsima/Fast-DDS#3822, open; a
  // restarted cloud_assembly then dropped every scan, "frames 'map' and 'laser' are not
  // connected"). Written anew, it goes the ordinary reliable way; the copies are identical.
  void republish_mount_to_new_readers() {
    const size_t matched = tf_static_.readers_matched_ever();
    if (matched == mount_readers_) return;
    mount_readers_ = matched;
    tf_static_.write(mount_);
    ++health_.counter("mount_republished");
  }

  // A barometer jump is left out of the fusion (FusionSettings::baro_gate_time): counted,
  // and said in Health at most once a second while it lasts.
  void report_barometer_outliers() {
    const uint64_t outliers = estimator_.fusion().barometer_outliers();
    auto& counter = health_.counter("pressures_outlying");
    if (outliers == counter) return;
    counter = outliers;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_outlier_report_ < std::chrono::seconds(1)) return;
    last_outlier_report_ = now;
    health_.error("barometer more than 5 sigma off the fused height (" + std::to_string(outliers) + " samples so far)");
  }

  void reject(const char* counter, const std::string& why) {
    ++health_.counter(counter);
    health_.error(why);
  }

  void publish_ready(bool input_ended = false) {
    if (!input_ended) last_input_ = std::chrono::steady_clock::now();
    report_barometer_outliers();
    for (const auto& pose : estimator_.take_ready(input_ended)) {
      if (input_ended) ++health_.counter("poses_after_input_ended");
      poses_.write(pose_message(pose));
      Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
      body.translation() = pose.position;
      body.linear() = pose.orientation.toRotationMatrix();
      tf2_msgs::msg::TFMessage tf;
      tf.transforms().push_back(transform_message(pose.stamp, frames_.map, frames_.body, body));
      tf_.write(tf);
      ++health_.counter("poses");
      if (!pose.has_attitude || !pose.has_position) ++health_.counter("poses_held");  // IMU or GPS missing
      if (pose.height_change && !pose.match_used) ++health_.counter("changes_rejected");
      if (pose.clearance) ++health_.counter("clearances");  // poses whose scan showed the ground
      // Cells left out as steps or edges (FusionSettings::clearance_gate): a count, not a fault.
      health_.counter("ground_cells_gated") = estimator_.fusion().cells_gated();
    }
    for (const auto& pose : estimator_.take_settled(input_ended)) {
      settled_poses_.write(pose_message(pose));
      ++health_.counter("poses_settled");
    }
    health_.counter("settled_as_first_solved") = estimator_.settled_as_first_solved();
  }

  geometry_msgs::msg::PoseWithCovarianceStamped pose_message(const EstimatedPose& pose) const {
    geometry_msgs::msg::PoseWithCovarianceStamped message;
    message.header().stamp(to_stamp(pose.stamp));
    message.header().frame_id(frames_.map);
    message.pose().pose(to_pose_message(pose.position, pose.orientation));
    // Position variances on the diagonal; the attitude's are not estimated (left 0).
    for (int axis = 0; axis < 3; ++axis)
      message.pose().covariance()[axis * 7] = pose.position_sigma[axis] * pose.position_sigma[axis];
    return message;
  }

  std::shared_ptr<spdlog::logger> log_;
  HealthReporter& health_;
  std::chrono::steady_clock::time_point last_outlier_report_;
  PoseEstimatorSettings settings_;
  Frames frames_;
  double input_ended_after_;  // s of wall time
  std::chrono::steady_clock::time_point last_input_ = std::chrono::steady_clock::now();
  std::mutex mutex_;
  PoseEstimator estimator_;
  Writer<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType> poses_, settled_poses_;
  Writer<tf2_msgs::msg::TFMessagePubSubType> tf_;
  Writer<tf2_msgs::msg::TFMessagePubSubType> tf_static_;
  tf2_msgs::msg::TFMessage mount_;  // laser in base_link, for rt/tf_static
  size_t mount_readers_ = 0;
  std::unique_ptr<Reader<sensor_msgs::msg::ImuPubSubType>> imu_;
  std::unique_ptr<Reader<sensor_msgs::msg::NavSatFixPubSubType>> fixes_;
  std::unique_ptr<Reader<sensor_msgs::msg::FluidPressurePubSubType>> pressures_;
  std::unique_ptr<Reader<scanbus::msg::ScanMatchPubSubType>> matches_;
  std::unique_ptr<Reader<sensor_msgs::msg::LaserScanPubSubType>> scans_;
};

}  // namespace

std::unique_ptr<Service> make_pose_estimation(ServiceContext& context) {
  return std::make_unique<PoseEstimation>(context);
}

}  // namespace scanbus::pose_estimation
