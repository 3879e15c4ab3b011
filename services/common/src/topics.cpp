#include "scanbus/topics.hpp"

#include <stdexcept>

namespace scanbus {

namespace {

constexpr QosSettings kReliable{true, false, false, 10};
constexpr QosSettings kSensor{false, false, false, 10};  // best effort, like ROS 2 sensor data
constexpr QosSettings kLatched{true, true, false, 1};    // a late subscriber gets the last sample
constexpr QosSettings kTf{true, false, false, 100};      // as tf2 readers expect

}  // namespace

const std::vector<TopicInfo>& topic_catalogue() {
  static const std::vector<TopicInfo> catalogue = {
      {"rt/scanbus/health",
       "scanbus::msg::dds_::Health_",
       {true, false, false, 50},
       "every service",
       "scanbus health, monitoring",
       "Liveness, state and counters of each service, once per period."},
      {"rt/scanner/command", "scanbus::msg::dds_::ScannerCommand_", kReliable, "scanbus CLI, operators", "scanner_io",
       "Start, stop, status and resolution commands for the rotating scanner."},
      {"rt/scanner/status", "scanbus::msg::dds_::ScannerStatus_", kLatched, "scanner_io", "scanbus CLI",
       "Device state, firmware version, speed, line and checksum error counts."},
      {"rt/scanner/spherical", "scanbus::msg::dds_::SphericalScan_", kReliable, "scanner_io", "recorder",
       "Raw rotating-scanner measurements (yaw, pitch, range, signal) in batches."},
      {"rt/scanner/cloud", "sensor_msgs::msg::dds_::PointCloud2_", kLatched, "scanner_io", "scanbus demo, recorder",
       "One point cloud per completed revolution (one pitch ring), frame scanner."},
      {"rt/scanner/scan_cloud", "sensor_msgs::msg::dds_::PointCloud2_", kLatched, "scanner_io",
       "room_measurement, scanbus demo", "The whole scan's cloud (every pitch step), frame scanner."},
      {"rt/scan", "sensor_msgs::msg::dds_::LaserScan_", kSensor, "sensor_replay",
       "scan_matcher, cloud_assembly, pose_estimation", "2D laser scans of the MAV's downward-looking laser."},
      {"rt/imu", "sensor_msgs::msg::dds_::Imu_", kSensor, "sensor_replay", "pose_estimation, scan_matcher",
       "MAV attitude from the IMU."},
      {"rt/fix", "sensor_msgs::msg::dds_::NavSatFix_", kSensor, "sensor_replay", "pose_estimation",
       "MAV GPS position."},
      {"rt/pressure", "sensor_msgs::msg::dds_::FluidPressure_", kSensor, "sensor_replay", "pose_estimation",
       "MAV barometer, in Pa."},
      {"rt/truth/pose",
       "geometry_msgs::msg::dds_::PoseStamped_",
       {true, false, false, 100},
       "sensor_replay (simulated flights)",
       "tests, RViz2",
       "Ground truth of the MAV's base_link in the map frame, where a flight has it."},
      {"rt/scan_match", "scanbus::msg::dds_::ScanMatch_", kReliable, "scan_matcher", "pose_estimation",
       "PL-ICP result per scan: cumulative and incremental pose, covariance, quality."},
      {"rt/pose", "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_", kReliable, "pose_estimation",
       "RViz2, controllers", "Fused MAV pose in the map frame, as first solved (at once)."},
      // Written in bursts: half a second of poses at each slide, the window's 3.5 s when the
      // input ends; kept whole for a reader catching up.
      {"rt/pose/settled",
       "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_",
       {true, false, false, 1000},
       "pose_estimation",
       "cloud_assembly, scanbus demo",
       "The same poses as their height leaves the fusion's window (3 s later), solved with the samples after it."},
      {"rt/tf", "tf2_msgs::msg::dds_::TFMessage_", kTf, "pose_estimation",
       "RViz2, cloud_assembly (settled_poses: false)", "Dynamic transforms (base_link to map)."},
      {"rt/tf_static",
       "tf2_msgs::msg::dds_::TFMessage_",
       {true, true, false, 100},
       "pose_estimation",
       "cloud_assembly, RViz2",
       "Static transforms (laser to base_link) from config."},
      {"rt/cloud/assembled", "sensor_msgs::msg::dds_::PointCloud2_", kLatched, "cloud_assembly", "recorder, RViz2",
       "Accumulated ground-surface cloud in the map frame."},
      {"rt/cloud/elevation", "sensor_msgs::msg::dds_::PointCloud2_", kLatched, "cloud_assembly", "recorder, RViz2",
       "The assembled cloud's elevation grid: one point per cell with a height (x y z stdev, map frame)."},
      {"rt/cloud/assemble_request", "scanbus::msg::dds_::AssembleRequest_", kReliable, "any client", "cloud_assembly",
       "Ask for the cloud of a time window (request id correlates the reply)."},
      {"rt/cloud/assemble_reply", "scanbus::msg::dds_::AssembleReply_", kReliable, "cloud_assembly",
       "the requesting client", "Cloud of the requested window, with the request id."},
      {"rt/clock",
       "rosgraph_msgs::msg::dds_::Clock_",
       {false, false, false, 1},
       "scanbus replay --clock",
       "foxglove_bridge (sim_time), RViz2 (use_sim_time)",
       "The replayed recording's time, at each message it publishes (as ros2 bag play --clock)."},
      {"rt/room/measurement", "scanbus::msg::dds_::RoomMeasurement_", kLatched, "room_measurement",
       "scanbus CLI, recorder",
       "Walls, corners, wall lengths, floor area and ceiling height, stamped with the last scan cloud measured."},
      {"rt/room/walls", "sensor_msgs::msg::dds_::PointCloud2_", kLatched, "room_measurement", "RViz2",
       "Wall inliers coloured per wall (x y z rgb), stamped as the measurement."},
  };
  return catalogue;
}

const TopicInfo* find_topic(const std::string& name) {
  for (const auto& topic : topic_catalogue())
    if (topic.name == name) return &topic;
  return nullptr;
}

const TopicInfo& topic_info(const std::string& name) {
  if (const TopicInfo* topic = find_topic(name)) return *topic;
  throw std::invalid_argument("unknown topic '" + name + "' (see 'scanbus topics')");
}

QosSettings qos_from_config(const Config& qos_section, const TopicInfo& topic) {
  QosSettings qos = topic.qos;
  if (!qos_section.has(topic.name)) return qos;
  const Config entry = qos_section.section(topic.name);
  const auto def = [](bool value, const char* yes, const char* no) { return value ? yes : no; };
  qos.reliable = entry.choice("reliability", def(qos.reliable, "reliable", "best_effort"),
                              {"reliable", "best_effort"}) == "reliable";
  qos.transient_local = entry.choice("durability", def(qos.transient_local, "transient_local", "volatile"),
                                     {"transient_local", "volatile"}) == "transient_local";
  qos.keep_all =
      entry.choice("history", def(qos.keep_all, "keep_all", "keep_last"), {"keep_all", "keep_last"}) == "keep_all";
  qos.depth = static_cast<int>(entry.integer("depth", qos.depth, 1, 100000));
  return qos;
}

std::string describe(const QosSettings& qos) {
  std::string text = qos.reliable ? "reliable" : "best_effort";
  text += qos.transient_local ? ", transient_local" : ", volatile";
  text += qos.keep_all ? ", keep_all" : ", keep_last " + std::to_string(qos.depth);
  return text;
}

}  // namespace scanbus
