#include <gtest/gtest.h>

#include "scanbus/json.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/topics.hpp"
#include "scanbus_msgs/HeaderPubSubTypes.h"
#include "scanbus_msgs/TimePubSubTypes.h"
#include "scanbus_msgs/TransformStampedPubSubTypes.h"

using namespace scanbus;

// What ROS 2 (rmw_fastrtps, rmw_cyclonedds) registers for these types: a ROS 2 node only
// matches our topics when these strings are identical.
TEST(Types, RegisteredNamesAreTheRos2Ones) {
  EXPECT_EQ(sensor_msgs::msg::LaserScanPubSubType().getName(), std::string("sensor_msgs::msg::dds_::LaserScan_"));
  EXPECT_EQ(sensor_msgs::msg::PointCloud2PubSubType().getName(), std::string("sensor_msgs::msg::dds_::PointCloud2_"));
  EXPECT_EQ(sensor_msgs::msg::ImuPubSubType().getName(), std::string("sensor_msgs::msg::dds_::Imu_"));
  EXPECT_EQ(sensor_msgs::msg::NavSatFixPubSubType().getName(), std::string("sensor_msgs::msg::dds_::NavSatFix_"));
  EXPECT_EQ(sensor_msgs::msg::FluidPressurePubSubType().getName(),
            std::string("sensor_msgs::msg::dds_::FluidPressure_"));
  EXPECT_EQ(geometry_msgs::msg::PoseWithCovarianceStampedPubSubType().getName(),
            std::string("geometry_msgs::msg::dds_::PoseWithCovarianceStamped_"));
  EXPECT_EQ(geometry_msgs::msg::TransformStampedPubSubType().getName(),
            std::string("geometry_msgs::msg::dds_::TransformStamped_"));
  EXPECT_EQ(tf2_msgs::msg::TFMessagePubSubType().getName(), std::string("tf2_msgs::msg::dds_::TFMessage_"));
  EXPECT_EQ(std_msgs::msg::HeaderPubSubType().getName(), std::string("std_msgs::msg::dds_::Header_"));
  EXPECT_EQ(builtin_interfaces::msg::TimePubSubType().getName(), std::string("builtin_interfaces::msg::dds_::Time_"));
  EXPECT_EQ(scanbus::msg::RoomMeasurementPubSubType().getName(), std::string("scanbus::msg::dds_::RoomMeasurement_"));
}

TEST(Types, NoTypeIsKeyed) {
  // Keyed and unkeyed topics never match, and ROS 2 types are unkeyed.
  EXPECT_FALSE(sensor_msgs::msg::PointCloud2PubSubType().m_isGetKeyDefined);
  EXPECT_FALSE(scanbus::msg::AssembleRequestPubSubType().m_isGetKeyDefined);
  EXPECT_FALSE(scanbus::msg::HealthPubSubType().m_isGetKeyDefined);
}

TEST(Types, EveryCatalogueTypeIsKnown) {
  for (const auto& topic : topic_catalogue()) EXPECT_TRUE(visit_message_type(topic.type, [](auto) {})) << topic.type;
  EXPECT_FALSE(visit_message_type("std_msgs::msg::dds_::String_", [](auto) {}));
}

// A ROS 2 subscriber decodes our bytes: check the CDR layout of a Header against the bytes
// ROS 2 puts on the wire (encapsulation CDR_LE, int32 sec, uint32 nanosec, string with
// length including the terminating NUL).
TEST(Types, HeaderSerialisesAsRos2Does) {
  std_msgs::msg::Header header;
  header.stamp().sec(1);
  header.stamp().nanosec(2);
  header.frame_id("map");
  std_msgs::msg::HeaderPubSubType type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.m_typeSize);
  ASSERT_TRUE(type.serialize(&header, &payload));
  const std::vector<uint8_t> expected = {0x00, 0x01, 0x00, 0x00, 1, 0, 0, 0, 2, 0, 0, 0, 4, 0, 0, 0, 'm', 'a', 'p', 0};
  ASSERT_EQ(payload.length, expected.size());
  EXPECT_TRUE(std::equal(expected.begin(), expected.end(), payload.data));
}

TEST(Types, JsonUsesRos2FieldNames) {
  sensor_msgs::msg::LaserScan scan;
  scan.header().frame_id("laser");
  scan.ranges({1.0f, 2.0f});
  const nlohmann::json json = scan;
  EXPECT_EQ(json["header"]["frame_id"], "laser");
  EXPECT_EQ(json["ranges"].size(), 2u);
  EXPECT_TRUE(json.contains("angle_increment"));
}
