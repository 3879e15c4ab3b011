// ROS 2 message definitions (.msg text) of scanbus's types, made from the project's own IDL
// (idl/*.idl, compiled in) so recordings carry schemas that Foxglove and rosbag2 decode:
// the MCAP `ros2msg` schema encoding, top-level definition first, then each dependency
// after a line of 80 '=' and "MSG: pkg/Type".
//
// Only the IDL subset scanbus writes is understood: modules, structs, constants in
// `<Struct>_Constants` modules, primitive, string, nested, sequence<> and fixed-array members.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace scanbus::recorder {

class Ros2MsgError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Ros2MsgCatalogue {
 public:
  // Parses IDL texts; throws Ros2MsgError naming the construct it does not understand.
  explicit Ros2MsgCatalogue(const std::vector<std::string>& idl_texts);
  // scanbus's own types, from the IDL compiled into the binary.
  static const Ros2MsgCatalogue& scanbus();

  bool contains(const std::string& ros_type) const { return definitions_.count(ros_type) > 0; }
  // The .msg text of one type (e.g. "sensor_msgs/msg/LaserScan"), without dependencies.
  const std::string& definition(const std::string& ros_type) const;
  // The complete `ros2msg` schema: the type's definition and every type it uses.
  std::string schema(const std::string& ros_type) const;

 private:
  struct Definition {
    std::string text;
    std::vector<std::string> dependencies;  // ROS type names of nested members, in order
  };
  void collect(const std::string& ros_type, std::vector<std::string>& order) const;

  std::map<std::string, Definition> definitions_;
  friend class IdlParser;
};

// "sensor_msgs::msg::dds_::LaserScan_" <-> "sensor_msgs/msg/LaserScan" (ROS 2's type
// mangling on DDS); throws Ros2MsgError for names not in that form.
std::string ros_type_of_dds_type(const std::string& dds_type);
std::string dds_type_of_ros_type(const std::string& ros_type);
// "rt/scan" <-> "/scan" (ROS 2's topic prefix on DDS).
std::string ros_topic_of_dds_topic(const std::string& dds_topic);
std::string dds_topic_of_ros_topic(const std::string& ros_topic);

}  // namespace scanbus::recorder
