// Every generated message type, and dispatch from a registered type name to its PubSubType.
#pragma once

#include <string>
#include <vector>

#include "scanbus_msgs/AssemblePubSubTypes.h"
#include "scanbus_msgs/ClockPubSubTypes.h"
#include "scanbus_msgs/FluidPressurePubSubTypes.h"
#include "scanbus_msgs/HealthPubSubTypes.h"
#include "scanbus_msgs/ImuPubSubTypes.h"
#include "scanbus_msgs/LaserScanPubSubTypes.h"
#include "scanbus_msgs/NavSatFixPubSubTypes.h"
#include "scanbus_msgs/PointCloud2PubSubTypes.h"
#include "scanbus_msgs/PoseStampedPubSubTypes.h"
#include "scanbus_msgs/PoseWithCovarianceStampedPubSubTypes.h"
#include "scanbus_msgs/RoomMeasurementPubSubTypes.h"
#include "scanbus_msgs/ScanMatchPubSubTypes.h"
#include "scanbus_msgs/ScannerCommandPubSubTypes.h"
#include "scanbus_msgs/ScannerStatusPubSubTypes.h"
#include "scanbus_msgs/SphericalScanPubSubTypes.h"
#include "scanbus_msgs/TFMessagePubSubTypes.h"

namespace scanbus {

template <class PubSubType>
struct TypeTag {
  using type = PubSubType;
};

// The top-level types topics carry. Calls f(TypeTag<PubSubType>{}) for the one registered
// as `type_name`; false when none is.
template <class F>
bool visit_message_type(const std::string& type_name, F&& f) {
  bool found = false;
  auto try_one = [&](auto tag) {
    using PubSubType = typename decltype(tag)::type;
    if (!found && PubSubType().getName() == type_name) {
      found = true;
      f(tag);
    }
  };
  try_one(TypeTag<sensor_msgs::msg::LaserScanPubSubType>{});
  try_one(TypeTag<sensor_msgs::msg::PointCloud2PubSubType>{});
  try_one(TypeTag<sensor_msgs::msg::ImuPubSubType>{});
  try_one(TypeTag<sensor_msgs::msg::FluidPressurePubSubType>{});
  try_one(TypeTag<sensor_msgs::msg::NavSatFixPubSubType>{});
  try_one(TypeTag<geometry_msgs::msg::PoseStampedPubSubType>{});
  try_one(TypeTag<geometry_msgs::msg::PoseWithCovarianceStampedPubSubType>{});
  try_one(TypeTag<tf2_msgs::msg::TFMessagePubSubType>{});
  try_one(TypeTag<scanbus::msg::SphericalScanPubSubType>{});
  try_one(TypeTag<scanbus::msg::ScannerCommandPubSubType>{});
  try_one(TypeTag<scanbus::msg::ScannerStatusPubSubType>{});
  try_one(TypeTag<scanbus::msg::ScanMatchPubSubType>{});
  try_one(TypeTag<scanbus::msg::RoomMeasurementPubSubType>{});
  try_one(TypeTag<scanbus::msg::AssembleRequestPubSubType>{});
  try_one(TypeTag<scanbus::msg::AssembleReplyPubSubType>{});
  try_one(TypeTag<scanbus::msg::HealthPubSubType>{});
  try_one(TypeTag<rosgraph_msgs::msg::ClockPubSubType>{});
  return found;
}

}  // namespace scanbus
