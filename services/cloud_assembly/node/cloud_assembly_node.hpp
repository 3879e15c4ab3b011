#pragma once

#include "scanbus/service.hpp"

namespace scanbus::cloud_assembly {

// Config section `cloud_assembly` (config/services/cloud_assembly.yaml lists every key):
// rt/scan, rt/pose/settled (or rt/tf: settled_poses), rt/tf_static in; the accumulated, height-coloured ground cloud on
// rt/cloud/assembled, and the cloud of any time window on request (rt/cloud/assemble_*).
std::unique_ptr<Service> make_cloud_assembly(ServiceContext& context);

}  // namespace scanbus::cloud_assembly
