// A RoomResult for people (text) and programs (JSON), shared by `room measure` and `demo`.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "scanbus/room_measurement/room_measurement.hpp"

namespace scanbus::cli {

nlohmann::json room_json(const room_measurement::RoomResult& room);
std::string room_text(const room_measurement::RoomResult& room);

}  // namespace scanbus::cli
