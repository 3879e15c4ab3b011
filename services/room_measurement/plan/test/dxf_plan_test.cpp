#include "scanbus/room_plan/dxf_plan.hpp"

#include <dxflib/dl_creationadapter.h>
#include <dxflib/dl_dxf.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <map>

namespace scanbus::room_plan {
namespace {

using room_measurement::RoomResult;

// What a CAD program would read back: lines per layer, aligned dimensions, texts, units.
struct DrawingReader : DL_CreationAdapter {
  std::map<std::string, std::vector<DL_LineData>> lines;
  std::map<std::string, std::vector<DL_TextData>> texts;
  std::vector<std::string> layers;
  int units = -1;

  void addLayer(const DL_LayerData& data) override { layers.push_back(data.name); }
  void addLine(const DL_LineData& data) override { lines[attributes.getLayer()].push_back(data); }
  void addText(const DL_TextData& data) override { texts[attributes.getLayer()].push_back(data); }
  bool has_text(const char* layer, const std::string& text) const {
    if (!texts.count(layer)) return false;
    const auto& on = texts.at(layer);
    return std::any_of(on.begin(), on.end(), [&](const DL_TextData& t) { return t.text == text; });
  }
  void setVariableInt(const std::string& key, int value, int) override {
    if (key == "$INSUNITS") units = value;
  }
};

double length_of(const std::vector<DL_LineData>& lines) {
  double sum = 0;
  for (const auto& l : lines) sum += std::hypot(l.x2 - l.x1, l.y2 - l.y1);
  return sum;
}

// A 4 m x 3 m room around the scanner, a 0.9 m door in its first wall.
RoomResult door_room() {
  RoomResult room;
  room.corners = {{-1, -1}, {3, -1}, {3, 2}, {-1, 2}};
  const Eigen::Vector2d normals[] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
  for (int w = 0; w < 4; ++w) {
    room_measurement::MeasuredWall wall;
    wall.line.normal = normals[w];
    wall.length = (room.corners[(w + 1) % 4] - room.corners[w]).norm();
    wall.length_sigma = 0.004;
    room.walls.push_back(wall);
  }
  room.walls[0].openings = {{1.2, 0.9}};
  room.area = 12;
  room.area_sigma = 0.02;
  room.perimeter = 14;
  room.floor_z = -1.2;
  room.ceiling_z = 1.3;
  return room;
}

DrawingReader read_back(const std::string& path) {
  DrawingReader reader;
  DL_Dxf dxf;
  EXPECT_TRUE(dxf.in(path, &reader)) << path;
  return reader;
}

std::string temp_path(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::to_string(getpid()) + name)).string();
}

TEST(DxfPlan, WallsOpeningsDimensionsAndAreaReadBack) {
  const std::string path = temp_path("_plan.dxf");
  write_dxf_plan(path, door_room(), "test room");
  const DrawingReader drawing = read_back(path);
  std::filesystem::remove(path);

  EXPECT_EQ(drawing.units, 6);  // metres
  for (const char* layer : {kWallLayer, kOpeningLayer, kDimensionLayer, kTextLayer})
    EXPECT_NE(std::find(drawing.layers.begin(), drawing.layers.end(), layer), drawing.layers.end()) << layer;
  // The door is left open in the wall: 14 m of perimeter, 0.9 m of it on OPENINGS.
  EXPECT_NEAR(length_of(drawing.lines.at(kWallLayer)), 14 - 0.9, 1e-6);
  ASSERT_EQ(drawing.lines.at(kOpeningLayer).size(), 1u);
  const DL_LineData& door = drawing.lines.at(kOpeningLayer)[0];
  EXPECT_NEAR(door.x1, 0.2, 1e-6);
  EXPECT_NEAR(door.x2, 1.1, 1e-6);
  EXPECT_NEAR(door.y1, -1, 1e-6);
  // Per wall two extension lines, two ticks and the dimension line outside the room; its text
  // the length and its sigma, along the wall.
  ASSERT_EQ(drawing.lines.at(kDimensionLayer).size(), 4u * 5);
  const DL_LineData& first = drawing.lines.at(kDimensionLayer)[4];
  EXPECT_NEAR(first.x1, -1, 1e-6);
  EXPECT_NEAR(first.x2, 3, 1e-6);
  EXPECT_NEAR(first.y1, -1.35, 1e-6);
  ASSERT_EQ(drawing.texts.at(kDimensionLayer).size(), 4u);
  EXPECT_EQ(drawing.texts.at(kDimensionLayer)[0].text, "4.000 m %%p 0.004");
  EXPECT_EQ(drawing.texts.at(kDimensionLayer)[1].text, "3.000 m %%p 0.004");
  EXPECT_NEAR(drawing.texts.at(kDimensionLayer)[1].angle, 90, 1e-6);  // along the wall at x = 3
  EXPECT_TRUE(drawing.has_text(kTextLayer, "opening 0.90 m"));
  EXPECT_TRUE(drawing.has_text(kTextLayer, "floor area 12.00 m2 %%p 0.02"));
  EXPECT_TRUE(drawing.has_text(kTextLayer, "ceiling height 2.50 m"));
}

TEST(DxfPlan, RoomThatDidNotCloseShowsCandidatesAndWhy) {
  RoomResult room;
  room.status = room_measurement::RoomStatus::WallsDoNotClose;
  room.message = "no wall seen over 95 degrees";
  room_measurement::WallLine candidate;
  candidate.normal = {1, 0};
  candidate.offset = 2;
  candidate.start = -1;
  candidate.end = 1.5;
  room.candidates = {candidate};
  const std::string path = temp_path("_open.dxf");
  write_dxf_plan(path, room, "open room");
  const DrawingReader drawing = read_back(path);
  std::filesystem::remove(path);
  ASSERT_EQ(drawing.lines.at(kWallLayer).size(), 1u);
  EXPECT_NEAR(length_of(drawing.lines.at(kWallLayer)), 2.5, 1e-6);
  EXPECT_EQ(drawing.lines.count(kDimensionLayer), 0u);
  EXPECT_TRUE(
      drawing.has_text(kTextLayer, "not measured: walls_do_not_close: no wall seen over 95 degrees (candidate walls)"));
}

TEST(DxfPlan, UnwritablePathIsAnErrorNamingIt) {
  try {
    write_dxf_plan("/nonexistent-dir/plan.dxf", door_room(), "x");
    FAIL() << "no error";
  } catch (const DxfPlanError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/plan.dxf"), std::string::npos);
  }
}

}  // namespace
}  // namespace scanbus::room_plan
