// Rooms as YAML (config/rooms/*.yaml):
//   name: thesis case 1
//   corners: [[0, 0], [5.47, 0], [5.47, 3.48], [0, 3.48]]   # m, counter-clockwise
//   ceiling: 2.5                                            # m
//   outside: 3.0               # m: floor and ceiling reach this far past the walls (seen through doors)
//   scanner: {position: [2.0, 1.5, 1.2], heading: 0}       # m; degrees
//   openings: [{wall: 2, from: 0.6, to: 1.5, bottom: 0, top: 2.0}]   # doors; windows have bottom > 0
//   outside_walls: [[x0, y0, x1, y1]]   # m: floor-to-ceiling walls outside, seen through openings
//   boxes: [{min: [0, 0, 0], max: [0.8, 2.0, 0.75]}]
#pragma once

#include <string>

#include "scanbus/config.hpp"
#include "scanbus/sim/room_model.hpp"

namespace scanbus::sim {

// Throws ConfigError naming the file and key.
RoomModel load_room(const Config& room);
RoomModel load_room_file(const std::string& path);
// The room as such a file (load_room reads it back): a generated room made reproducible.
std::string room_to_yaml(const RoomModel& room);

}  // namespace scanbus::sim
