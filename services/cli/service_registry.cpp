#include "service_registry.hpp"

#include "cloud_assembly_node.hpp"
#include "foxglove_bridge_node.hpp"
#include "pose_estimation_node.hpp"
#include "recorder_node.hpp"
#include "room_measurement_node.hpp"
#include "scan_matcher_node.hpp"
#include "scanner_io_node.hpp"
#include "sensor_replay_node.hpp"

namespace scanbus::cli {

const std::map<std::string, ServiceFactory>& service_registry() {
  static const std::map<std::string, ServiceFactory> registry = {
      {"cloud_assembly", cloud_assembly::make_cloud_assembly},
      {"foxglove_bridge", foxglove_bridge::make_foxglove_bridge},
      {"pose_estimation", pose_estimation::make_pose_estimation},
      {"recorder", recorder::make_recorder},
      {"room_measurement", room_measurement::make_room_measurement},
      {"scan_matcher", scan_matcher::make_scan_matcher},
      {"scanner_io", scanner_io::make_scanner_io},
      {"sensor_replay", sensor_replay::make_sensor_replay},
  };
  return registry;
}

}  // namespace scanbus::cli
