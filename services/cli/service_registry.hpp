// The services `scanbus run NAME` can start; each also has its own executable.
#pragma once

#include <map>
#include <string>

#include "scanbus/service.hpp"

namespace scanbus::cli {

const std::map<std::string, ServiceFactory>& service_registry();

}  // namespace scanbus::cli
