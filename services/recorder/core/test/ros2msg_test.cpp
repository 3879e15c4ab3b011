#include <gtest/gtest.h>

#include "scanbus/recorder/ros2msg.hpp"
#include "scanbus/topics.hpp"

namespace scanbus::recorder {
namespace {

const std::string kDelimiter(80, '=');

TEST(Ros2Msg, LaserScanIsRos2sDefinitionWithItsDependencies) {
  const auto& catalogue = Ros2MsgCatalogue::scanbus();
  EXPECT_EQ(catalogue.schema("sensor_msgs/msg/LaserScan"),
            "std_msgs/Header header\n"
            "float32 angle_min\n"
            "float32 angle_max\n"
            "float32 angle_increment\n"
            "float32 time_increment\n"
            "float32 scan_time\n"
            "float32 range_min\n"
            "float32 range_max\n"
            "float32[] ranges\n"
            "float32[] intensities\n" +
                kDelimiter + "\nMSG: std_msgs/Header\n" +
                "builtin_interfaces/Time stamp\n"
                "string frame_id\n" +
                kDelimiter + "\nMSG: builtin_interfaces/Time\n" +
                "int32 sec\n"
                "uint32 nanosec\n");
}

TEST(Ros2Msg, ConstantsFixedArraysAndNestedSequences) {
  const auto& catalogue = Ros2MsgCatalogue::scanbus();
  const std::string& room = catalogue.definition("scanbus/msg/RoomMeasurement");
  EXPECT_EQ(room.rfind("uint8 OK=0\nuint8 TOO_FEW_POINTS=1\n", 0), 0u) << room;
  EXPECT_NE(room.find("scanbus/Wall[] walls\n"), std::string::npos);
  EXPECT_NE(room.find("geometry_msgs/Point[] corners\n"), std::string::npos);
  EXPECT_NE(catalogue.definition("scanbus/msg/Wall").find("float64[4] plane\n"), std::string::npos);
  const std::string schema = catalogue.schema("scanbus/msg/RoomMeasurement");
  EXPECT_NE(schema.find("MSG: scanbus/Wall\n"), std::string::npos);
  EXPECT_EQ(schema.find("MSG: std_msgs/Header\n"), schema.rfind("MSG: std_msgs/Header\n")) << "each dependency once";
}

TEST(Ros2Msg, EveryCatalogueTopicHasASchema) {
  for (const auto& topic : topic_catalogue()) {
    const std::string ros_type = ros_type_of_dds_type(topic.type);
    EXPECT_TRUE(Ros2MsgCatalogue::scanbus().contains(ros_type)) << topic.name << " " << ros_type;
    EXPECT_EQ(dds_type_of_ros_type(ros_type), topic.type);
  }
}

TEST(Ros2Msg, NamesBetweenDdsAndRos) {
  EXPECT_EQ(ros_type_of_dds_type("sensor_msgs::msg::dds_::PointCloud2_"), "sensor_msgs/msg/PointCloud2");
  EXPECT_THROW(ros_type_of_dds_type("LaserScan"), Ros2MsgError);
  EXPECT_THROW(dds_type_of_ros_type("LaserScan"), Ros2MsgError);
  EXPECT_EQ(ros_topic_of_dds_topic("rt/scanner/cloud"), "/scanner/cloud");
  EXPECT_EQ(dds_topic_of_ros_topic("/scanner/cloud"), "rt/scanner/cloud");
  EXPECT_EQ(dds_topic_of_ros_topic("rt/scan"), "rt/scan");
}

TEST(Ros2Msg, IdlOutsideTheUnderstoodSubsetIsNamed) {
  try {
    Ros2MsgCatalogue({"module a { module msg { union U switch (long) { case 1: long x; }; }; };"});
    FAIL();
  } catch (const Ros2MsgError& error) {
    EXPECT_NE(std::string(error.what()).find("union"), std::string::npos) << error.what();
  }
  EXPECT_THROW(Ros2MsgCatalogue({"module a { module msg { struct S { b::msg::Missing m; }; }; };"}), Ros2MsgError);
}

}  // namespace
}  // namespace scanbus::recorder
