#pragma once

#include "scanbus/service.hpp"

namespace scanbus::recorder {

// Config section `recorder` (config/services/recorder.yaml lists every key): records the
// listed topics (all of the catalogue by default) to an MCAP file until stopped, then
// closes it with its summary.
std::unique_ptr<Service> make_recorder(ServiceContext& context);

}  // namespace scanbus::recorder
