#pragma once

#include "scanbus/service.hpp"

namespace scanbus::foxglove_bridge {

// Config section `foxglove_bridge` (config/services/foxglove_bridge.yaml lists every key): a
// Foxglove WebSocket server that offers every catalogue topic a writer publishes as a
// channel and forwards its samples' CDR bytes unchanged to the clients that subscribe.
std::unique_ptr<Service> make_foxglove_bridge(ServiceContext& context);

}  // namespace scanbus::foxglove_bridge
