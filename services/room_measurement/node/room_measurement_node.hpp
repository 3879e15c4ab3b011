#pragma once

#include "scanbus/room_measurement/room_measurement.hpp"
#include "scanbus/service.hpp"

namespace scanbus::room_measurement {

// Config section `room_measurement` (config/services/room_measurement.yaml lists every key):
//   scans: 3          # whole scans to accumulate before measuring: the thesis interleaves
//                     # three (eq. 4.9); one scan is too sparse for the histogram filter
//   frame_id: scanner
//   histogram, voxel_leaf, ransac, min_wall_height, min_wall_coverage, polygon: see
//   RoomSettings (core/include/scanbus/room_measurement/room_measurement.hpp)
std::unique_ptr<Service> make_room_measurement(ServiceContext& context);

// The whole section, for the service and for `scanbus room measure --config`, which reads
// the service's own file (and ignores scans and frame_id).
struct RoomServiceSettings {
  size_t scans = 3;
  std::string frame_id = "scanner";
  RoomSettings room;
};
RoomServiceSettings room_service_settings(const Config& section);
// The room settings of a service config file (its room_measurement section, every key
// checked); throws ConfigError naming the problem.
RoomSettings room_settings_from_file(const std::string& path);

}  // namespace scanbus::room_measurement
