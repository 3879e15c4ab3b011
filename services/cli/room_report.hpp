// A RoomResult for people (text) and programs (JSON), shared by `room measure` and `demo`; the
// room commands' --config.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

#include "scanbus/room_measurement/room_measurement.hpp"

namespace scanbus::cli {

nlohmann::json room_json(const room_measurement::RoomResult& room);
std::string room_text(const room_measurement::RoomResult& room);

// The room settings of a --config file (the defaults when `path` is empty), or nothing after
// "scanbus <command>: config error: ..." on stderr.
std::optional<room_measurement::RoomSettings> room_settings_for(const std::string& path, const std::string& command);

}  // namespace scanbus::cli
