#pragma once

#include "scanbus/service.hpp"

namespace scanbus::room_measurement {

// Config section `room_measurement` (config/services/room_measurement.yaml lists every key):
//   scans: 3          # whole scans to accumulate before measuring: the thesis interleaves
//                     # three (eq. 4.9); one scan is too sparse for the histogram filter
//   frame_id: scanner
//   histogram, voxel_leaf, ransac, min_wall_height, min_wall_coverage, polygon: see
//   RoomSettings (core/include/scanbus/room_measurement/room_measurement.hpp)
std::unique_ptr<Service> make_room_measurement(ServiceContext& context);

}  // namespace scanbus::room_measurement
