// Each topic of the catalogue (topics.hpp) with the type it carries. A Writer or Reader made
// from one is of that type or does not compile, and a topic's name is written once, here;
// `TypedTopics.MatchTheCatalogue` checks every name and type against the catalogue.
#pragma once

#include "scanbus/messages.hpp"

namespace scanbus {

template <class PubSubType>
struct Topic {
  using Type = PubSubType;
  const char* name;  // DDS topic name, with the ROS 2 "rt/" prefix
};

namespace topics {

inline constexpr Topic<msg::HealthPubSubType> kHealth{"rt/scanbus/health"};
inline constexpr Topic<msg::ScannerCommandPubSubType> kScannerCommand{"rt/scanner/command"};
inline constexpr Topic<msg::ScannerStatusPubSubType> kScannerStatus{"rt/scanner/status"};
inline constexpr Topic<msg::SphericalScanPubSubType> kScannerSpherical{"rt/scanner/spherical"};
inline constexpr Topic<sensor_msgs::msg::PointCloud2PubSubType> kScannerCloud{"rt/scanner/cloud"};
inline constexpr Topic<sensor_msgs::msg::PointCloud2PubSubType> kScannerScanCloud{"rt/scanner/scan_cloud"};
inline constexpr Topic<sensor_msgs::msg::LaserScanPubSubType> kScan{"rt/scan"};
inline constexpr Topic<sensor_msgs::msg::ImuPubSubType> kImu{"rt/imu"};
inline constexpr Topic<sensor_msgs::msg::NavSatFixPubSubType> kFix{"rt/fix"};
inline constexpr Topic<sensor_msgs::msg::FluidPressurePubSubType> kPressure{"rt/pressure"};
inline constexpr Topic<geometry_msgs::msg::PoseStampedPubSubType> kTruthPose{"rt/truth/pose"};
inline constexpr Topic<msg::ScanMatchPubSubType> kScanMatch{"rt/scan_match"};
inline constexpr Topic<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType> kPose{"rt/pose"};
inline constexpr Topic<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType> kPoseSettled{"rt/pose/settled"};
inline constexpr Topic<tf2_msgs::msg::TFMessagePubSubType> kTf{"rt/tf"};
inline constexpr Topic<tf2_msgs::msg::TFMessagePubSubType> kTfStatic{"rt/tf_static"};
inline constexpr Topic<sensor_msgs::msg::PointCloud2PubSubType> kCloudAssembled{"rt/cloud/assembled"};
inline constexpr Topic<sensor_msgs::msg::PointCloud2PubSubType> kCloudElevation{"rt/cloud/elevation"};
inline constexpr Topic<msg::AssembleRequestPubSubType> kAssembleRequest{"rt/cloud/assemble_request"};
inline constexpr Topic<msg::AssembleReplyPubSubType> kAssembleReply{"rt/cloud/assemble_reply"};
inline constexpr Topic<rosgraph_msgs::msg::ClockPubSubType> kClock{"rt/clock"};
inline constexpr Topic<msg::RoomMeasurementPubSubType> kRoomMeasurement{"rt/room/measurement"};
inline constexpr Topic<sensor_msgs::msg::PointCloud2PubSubType> kRoomWalls{"rt/room/walls"};

// Calls f(topic) for each of the above.
template <class F>
void for_each_typed_topic(F&& f) {
  f(kHealth), f(kScannerCommand), f(kScannerStatus), f(kScannerSpherical), f(kScannerCloud), f(kScannerScanCloud);
  f(kScan), f(kImu), f(kFix), f(kPressure), f(kTruthPose), f(kScanMatch), f(kPose), f(kPoseSettled), f(kTf);
  f(kTfStatic);
  f(kCloudAssembled), f(kCloudElevation), f(kAssembleRequest), f(kAssembleReply), f(kClock);
  f(kRoomMeasurement), f(kRoomWalls);
}

}  // namespace topics

}  // namespace scanbus
