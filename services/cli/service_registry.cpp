#include "service_registry.hpp"

namespace scanbus::cli {

const std::map<std::string, ServiceFactory>& service_registry() {
  static const std::map<std::string, ServiceFactory> registry = {};
  return registry;
}

}  // namespace scanbus::cli
