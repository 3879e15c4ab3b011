#include "service_registry.hpp"

#include "room_measurement_node.hpp"
#include "scan_matcher_node.hpp"
#include "scanner_io_node.hpp"

namespace scanbus::cli {

const std::map<std::string, ServiceFactory>& service_registry() {
  static const std::map<std::string, ServiceFactory> registry = {
      {"room_measurement", room_measurement::make_room_measurement},
      {"scan_matcher", scan_matcher::make_scan_matcher},
      {"scanner_io", scanner_io::make_scanner_io},
  };
  return registry;
}

}  // namespace scanbus::cli
