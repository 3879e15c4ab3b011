// The measured room as a floor plan a person checks at a glance: wall inliers, walls,
// corners, lengths, area. PNG or SVG (scanbus::plot), or DXF for CAD programs, by the
// file's extension.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "scanbus/room_measurement/room_measurement.hpp"

namespace scanbus::room_plan {

// `background`: points drawn faint grey under the plan (e.g. the whole scan). Throws
// std::runtime_error naming the file.
void write_floor_plan(const std::string& path, const room_measurement::RoomResult& room, const std::string& title,
                      const std::vector<Eigen::Vector3f>& background = {});

}  // namespace scanbus::room_plan
