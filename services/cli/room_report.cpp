#include "room_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "room_measurement_node.hpp"
#include "scanbus/units.hpp"

namespace scanbus::cli {

using room_measurement::RoomResult;

namespace {

nlohmann::json device_json(const room_measurement::DeviceEstimate& device) {
  nlohmann::json out = {{"state", room_measurement::device_state_name(device.state)}};
  if (device.state == room_measurement::DeviceEstimate::State::NotEstimated) return out;
  out["range_bias_m"] = device.range_bias;
  out["lever_arm_m"] = device.lever_arm;
  out["pitch_offset_deg"] = device.pitch_offset / kDegree;
  out["yaw_error_deg"] = device.yaw_error / kDegree;
  return out;
}

// One line on the scanner's own errors: applied, or wanted and held (a device to calibrate).
std::string device_text(const room_measurement::DeviceEstimate& device) {
  using State = room_measurement::DeviceEstimate::State;
  if (device.state == State::NotEstimated) return "";
  char line[256];
  std::snprintf(
      line, sizeof(line), "range bias %+.1f mm, lever arm %+.1f mm, pitch offset %+.2f deg, yaw error %.2f deg",
      device.range_bias * 1000, device.lever_arm * 1000, device.pitch_offset / kDegree, device.yaw_error / kDegree);
  if (device.state == State::Applied) return std::string("device corrections applied: ") + line + "\n";
  return std::string(
             "device terms not applied, beyond 3 sigmas of their priors (the walls fitted without them): "
             "the fit wanted ") +
         line + "\n";
}

}  // namespace

nlohmann::json room_json(const RoomResult& room) {
  nlohmann::json walls = nlohmann::json::array();
  for (const auto& wall : room.walls) {
    nlohmann::json openings = nlohmann::json::array();
    for (const auto& o : wall.openings)
      openings.push_back({{"start_m", o.start}, {"width_m", o.width}, {"depth_m", o.depth}});
    walls.push_back({{"length_m", wall.length},
                     {"inferred", wall.inferred()},
                     {"length_sigma_m", wall.length_sigma},
                     {"normal", {wall.line.normal.x(), wall.line.normal.y(), 0.0}},
                     {"distance_m", wall.line.offset},
                     {"rms_m", wall.line.rms},
                     {"inliers", wall.points},
                     {"openings", openings}});
  }
  nlohmann::json candidates = nlohmann::json::array();
  for (const auto& c : room.candidates)
    candidates.push_back({{"normal", {c.normal.x(), c.normal.y(), 0.0}},
                          {"distance_m", c.offset},
                          {"extent_m", {c.start, c.end}},
                          {"z_m", {c.z_low, c.z_high}},
                          {"inliers", c.inliers.size()}});
  nlohmann::json corners = nlohmann::json::array();
  for (const auto& corner : room.corners) corners.push_back({corner.x(), corner.y()});
  nlohmann::json corner_inferred = nlohmann::json::array();
  for (bool inferred : room.corner_inferred) corner_inferred.push_back(inferred);
  nlohmann::json out = {{"status", room_measurement::status_name(room.status)},
                        {"message", room.message},
                        {"walls", walls},
                        {"corners", corners},
                        {"corner_inferred", corner_inferred},
                        {"corner_sigmas_m", room.corner_sigmas},
                        {"candidates", candidates},
                        {"area_m2", room.area},
                        {"perimeter_m", room.perimeter},
                        {"area_sigma_m2", nullptr},
                        {"ceiling_height_m", nullptr},
                        {"ceiling_height_note", room.height_note},
                        {"points_in", room.points_in},
                        {"points_valid", room.points_valid},
                        {"points_after_filter", room.points_after_filter},
                        {"points_after_voxel", room.points_after_voxel},
                        {"voxel_overflow", room.voxel_overflow},
                        {"error_histogram", {{"bin_m", room.error_bin}, {"counts", room.error_histogram}}},
                        {"device", device_json(room.device)},
                        {"elapsed_ms", room.elapsed_ms}};
  if (room.ceiling_height()) out["ceiling_height_m"] = *room.ceiling_height();
  if (room.area_sigma > 0) out["area_sigma_m2"] = room.area_sigma;
  return out;
}

std::string room_text(const RoomResult& room) {
  char line[256];
  std::string text;
  if (room.status != room_measurement::RoomStatus::Ok) {
    std::snprintf(line, sizeof(line), "room not measured (%s): %s\n", room_measurement::status_name(room.status),
                  room.message.c_str());
    return line + device_text(room.device);
  }
  for (size_t i = 0; i < room.walls.size(); ++i) {
    const auto& wall = room.walls[i];
    if (wall.inferred()) {
      std::snprintf(line, sizeof(line),
                    "wall %zu: %.3f m (+-%.3f, not seen: inferred perpendicular between its neighbours", i + 1,
                    wall.length, wall.length_sigma);
    } else {
      std::snprintf(line, sizeof(line), "wall %zu: %.3f m (+-%.3f, rms %.3f m, %zu points", i + 1, wall.length,
                    wall.length_sigma, wall.line.rms, wall.points);
    }
    text += line;
    for (const auto& o : wall.openings) {
      std::snprintf(line, sizeof(line), "; opening %.2f m wide at %.2f m", o.width, o.start);
      text += line;
      if (o.depth > 0) {
        std::snprintf(line, sizeof(line), ", seen %.2f m through", o.depth);
        text += line;
      }
    }
    text += ")\n";
  }
  if (!room.corner_sigmas.empty()) {
    const auto [low, high] = std::minmax_element(room.corner_sigmas.begin(), room.corner_sigmas.end());
    std::snprintf(line, sizeof(line), "corners placed within +-%.3f to %.3f m (one sigma)\n", *low, *high);
    text += line;
  }
  std::snprintf(line, sizeof(line), "floor area %.2f m2", room.area);
  text += line;
  if (room.area_sigma > 0) {
    std::snprintf(line, sizeof(line), " (+-%.2f)", room.area_sigma);
    text += line;
  }
  std::snprintf(line, sizeof(line), ", perimeter %.2f m", room.perimeter);
  text += line;
  if (room.ceiling_height()) {
    std::snprintf(line, sizeof(line), ", ceiling height %.2f m", *room.ceiling_height());
    text += line;
  } else if (!room.height_note.empty()) {
    text += ", no ceiling height (" + room.height_note + ")";
  }
  if (room.points_in > 0) {
    std::snprintf(line, sizeof(line), " (%zu points, %.1f ms)", room.points_in, room.elapsed_ms);
    text += line;
  }
  return text + "\n" + device_text(room.device);
}

std::optional<room_measurement::RoomSettings> room_settings_for(const std::string& path, const std::string& command) {
  try {
    if (path.empty()) return room_measurement::RoomSettings{};
    return room_measurement::room_settings_from_file(path);
  } catch (const ConfigError& e) {
    std::cerr << "scanbus " << command << ": config error: " << e.what() << "\n";
    return std::nullopt;
  }
}

}  // namespace scanbus::cli
