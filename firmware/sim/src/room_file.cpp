#include "scanbus/sim/room_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <stdexcept>

namespace scanbus::sim {

RoomModel load_room(const Config& config) {
  RoomModel room;
  room.name = config.text("name", "room");
  for (const auto& corner : config.number_rows("corners", 2)) room.corners.emplace_back(corner[0], corner[1]);
  room.ceiling = config.number("ceiling", 2.5, 0.5, 20.0);
  room.outside = config.number("outside", 3.0, 0.0, 100.0);
  const Config scanner = config.section("scanner");
  const auto position = scanner.numbers("position", 3);
  room.scanner = Eigen::Vector3d(position[0], position[1], position[2]);
  room.heading = scanner.number("heading", 0.0, -360.0, 360.0) * M_PI / 180.0;
  for (const auto& entry : config.maps("openings")) {
    Opening opening;
    opening.wall = static_cast<size_t>(entry.integer("wall", 0, 0, 1000));
    opening.from = entry.number("from", 0.0, 0.0, 1000.0);
    opening.to = entry.number("to", 0.0, 0.0, 1000.0);
    opening.bottom = entry.number("bottom", 0.0, 0.0, 20.0);
    opening.top = entry.number("top", 2.0, 0.0, 20.0);
    room.openings.push_back(opening);
  }
  for (const auto& row :
       config.has("outside_walls") ? config.number_rows("outside_walls", 4) : std::vector<std::vector<double>>{})
    room.outside_walls.push_back({Eigen::Vector2d(row[0], row[1]), Eigen::Vector2d(row[2], row[3])});
  for (const auto& entry : config.maps("boxes")) {
    const auto min = entry.numbers("min", 3), max = entry.numbers("max", 3);
    room.boxes.push_back({Eigen::Vector3d(min[0], min[1], min[2]), Eigen::Vector3d(max[0], max[1], max[2])});
  }
  try {
    room.validate();
  } catch (const std::invalid_argument& e) {
    throw ConfigError(config.origin() + ": " + e.what());
  }
  return room;
}

RoomModel load_room_file(const std::string& path) {
  const Config config = Config::load(path);
  RoomModel room = load_room(config);
  config.check_all_read();
  return room;
}

std::string room_to_yaml(const RoomModel& room) {
  const auto row = [](std::initializer_list<double> values) {
    YAML::Node node(YAML::NodeType::Sequence);
    for (double v : values) node.push_back(v);
    node.SetStyle(YAML::EmitterStyle::Flow);
    return node;
  };
  YAML::Node root(YAML::NodeType::Map);
  root["name"] = room.name;
  for (const auto& c : room.corners) root["corners"].push_back(row({c.x(), c.y()}));
  root["corners"].SetStyle(YAML::EmitterStyle::Flow);
  root["ceiling"] = room.ceiling;
  root["outside"] = room.outside;
  root["scanner"]["position"] = row({room.scanner.x(), room.scanner.y(), room.scanner.z()});
  root["scanner"]["heading"] = room.heading * 180.0 / M_PI;
  for (const auto& o : room.openings) {
    YAML::Node opening;
    opening["wall"] = o.wall, opening["from"] = o.from, opening["to"] = o.to;
    opening["bottom"] = o.bottom, opening["top"] = o.top;
    opening.SetStyle(YAML::EmitterStyle::Flow);
    root["openings"].push_back(opening);
  }
  for (const auto& w : room.outside_walls)
    root["outside_walls"].push_back(row({w.from.x(), w.from.y(), w.to.x(), w.to.y()}));
  for (const auto& b : room.boxes) {
    YAML::Node box;
    box["min"] = row({b.min.x(), b.min.y(), b.min.z()});
    box["max"] = row({b.max.x(), b.max.y(), b.max.z()});
    box.SetStyle(YAML::EmitterStyle::Flow);
    root["boxes"].push_back(box);
  }
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace scanbus::sim
