// Built by ctest, not by `all`: with SCANBUS_WRONG_TYPE a Writer of LaserScans on the IMU's
// topic must not compile (test compile.topic_type_mismatch_is_an_error); without it, the
// same file must (compile.topic_type_match), so the failure is the type's, not the setup's.
#include "scanbus/dds.hpp"

void publish_scans(scanbus::Participant& participant) {
#ifdef SCANBUS_WRONG_TYPE
  scanbus::Writer<sensor_msgs::msg::LaserScanPubSubType> writer(participant, scanbus::topics::kImu);
#else
  scanbus::Writer<sensor_msgs::msg::LaserScanPubSubType> writer(participant, scanbus::topics::kScan);
#endif
  writer.write(sensor_msgs::msg::LaserScan());
}
