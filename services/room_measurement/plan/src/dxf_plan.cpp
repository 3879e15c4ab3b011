#include "scanbus/room_plan/dxf_plan.hpp"

#include <dxflib/dl_dxf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

namespace scanbus::room_plan {

namespace {

using room_measurement::RoomResult;

// ACI colours: walls white/black by background, openings cyan, dimensions green, text yellow,
// inferred walls magenta.
constexpr int kWallColour = 7, kOpeningColour = 4, kDimensionColour = 3, kTextColour = 2, kInferredColour = 6;
constexpr double kTextHeight = 0.12;       // m on the drawing: legible at a room's 1:50
constexpr double kDimensionOffset = 0.35;  // m outside the wall: clear of it at a room's 1:50

DL_Attributes on(const char* layer, int colour) { return DL_Attributes(layer, colour, -1, "CONTINUOUS", 1.0); }

// "5.472 m %%p 0.004": %%p is DXF's plus-minus sign; no sigma when none was estimated.
std::string metres(double value, double sigma, const char* unit = "m", int decimals = 3) {
  char text[64];
  if (sigma > 0)
    std::snprintf(text, sizeof(text), "%.*f %s %%%%p %.*f", decimals, value, unit, decimals, sigma);
  else
    std::snprintf(text, sizeof(text), "%.*f %s", decimals, value, unit);
  return text;
}

// The header, tables and blocks every CAD program expects before the entities (the order
// dxflib's writer documents); units metres.
void write_preamble(DL_Dxf& dxf, DL_WriterA& dw) {
  dxf.writeHeader(dw);
  dw.dxfString(9, "$INSUNITS");
  dw.dxfInt(70, 6);  // metres
  dw.dxfString(9, "$MEASUREMENT");
  dw.dxfInt(70, 1);  // metric
  dw.sectionEnd();
  dw.sectionTables();
  dxf.writeVPort(dw);
  dw.tableLinetypes(3);
  dxf.writeLinetype(dw, DL_LinetypeData("BYBLOCK", "BYBLOCK", 0, 0, 0.0));
  dxf.writeLinetype(dw, DL_LinetypeData("BYLAYER", "BYLAYER", 0, 0, 0.0));
  dxf.writeLinetype(dw, DL_LinetypeData("CONTINUOUS", "Continuous", 0, 0, 0.0));
  dw.tableEnd();
  dw.tableLayers(6);
  dxf.writeLayer(dw, DL_LayerData("0", 0), on("", kWallColour));
  dxf.writeLayer(dw, DL_LayerData(kWallLayer, 0), on("", kWallColour));
  dxf.writeLayer(dw, DL_LayerData(kOpeningLayer, 0), on("", kOpeningColour));
  dxf.writeLayer(dw, DL_LayerData(kInferredLayer, 0), on("", kInferredColour));
  dxf.writeLayer(dw, DL_LayerData(kDimensionLayer, 0), on("", kDimensionColour));
  dxf.writeLayer(dw, DL_LayerData(kTextLayer, 0), on("", kTextColour));
  dw.tableEnd();
  dw.tableStyle(1);
  dxf.writeStyle(dw, DL_StyleData("standard", 0, 0.0, 1.0, 0.0, 0, kTextHeight, "txt", ""));
  dw.tableEnd();
  dxf.writeView(dw);
  dxf.writeUcs(dw);
  dw.tableAppid(1);
  dxf.writeAppid(dw, "ACAD");
  dw.tableEnd();
  dxf.writeDimStyle(dw, 0.08, 0.05, 0.05, 0.03, kTextHeight);
  dxf.writeBlockRecord(dw);
  dw.tableEnd();
  dw.sectionEnd();
  dw.sectionBlocks();
  for (const char* block : {"*Model_Space", "*Paper_Space", "*Paper_Space0"}) {
    dxf.writeBlock(dw, DL_BlockData(block, 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(dw, block);
  }
  dw.sectionEnd();
}

void write_line(DL_Dxf& dxf, DL_WriterA& dw, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const char* layer,
                int colour) {
  dxf.writeLine(dw, DL_LineData(a.x(), a.y(), 0, b.x(), b.y(), 0), on(layer, colour));
}

void write_text(DL_Dxf& dxf, DL_WriterA& dw, const Eigen::Vector2d& at, const std::string& text,
                const char* layer = kTextLayer, int colour = kTextColour, double angle_deg = 0) {
  // Justification centre (1) and middle (2): `at` is the text's centre.
  dxf.writeText(
      dw, DL_TextData(at.x(), at.y(), 0, at.x(), at.y(), 0, kTextHeight, 1.0, 0, 1, 2, text, "standard", angle_deg),
      on(layer, colour));
}

// A builder's dimension outside the wall: extension lines, the dimension line with tick marks,
// its text along it. Drawn as lines and text, not a DIMENSION entity: dxflib writes DIMENSION
// without the block holding its picture, which strict readers (ezdxf's audit) then delete.
void write_dimension(DL_Dxf& dxf, DL_WriterA& dw, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                     const Eigen::Vector2d& outside, const std::string& text) {
  constexpr double kGap = 0.05, kTick = 0.06;  // m: extension lines clear of the wall; tick half-length
  const Eigen::Vector2d along = (b - a).normalized(), offset = outside * kDimensionOffset;
  for (const Eigen::Vector2d& end : {a, b}) {
    write_line(dxf, dw, end + outside * kGap, end + offset + outside * kGap, kDimensionLayer, kDimensionColour);
    const Eigen::Vector2d tick = (along + outside).normalized() * kTick;  // the architect's 45 degree slash
    write_line(dxf, dw, end + offset - tick, end + offset + tick, kDimensionLayer, kDimensionColour);
  }
  write_line(dxf, dw, a + offset, b + offset, kDimensionLayer, kDimensionColour);
  // Text along the line, upright (its angle kept within -90..90 degrees), just outside it.
  double angle = std::atan2(along.y(), along.x()) * 180 / M_PI;
  if (angle > 90) angle -= 180;
  if (angle <= -90) angle += 180;
  write_text(dxf, dw, (a + b) / 2 + offset + outside * 1.2 * kTextHeight, text, kDimensionLayer, kDimensionColour,
             angle);
}

// One wall corner a to corner b: the wall drawn where it is solid, its openings left open
// with a thin line across and their width, and its length as a dimension outside.
void write_wall(DL_Dxf& dxf, DL_WriterA& dw, const room_measurement::MeasuredWall& wall, const Eigen::Vector2d& a,
                const Eigen::Vector2d& b) {
  const double length = (b - a).norm();
  const Eigen::Vector2d along = (b - a) / length, outside = wall.line.normal;
  if (wall.inferred()) {  // not seen: its own layer, and said so beside its length
    write_line(dxf, dw, a, b, kInferredLayer, kInferredColour);
    write_text(dxf, dw, (a + b) / 2 - outside * 2 * kTextHeight, "not seen (inferred)");
    write_dimension(dxf, dw, a, b, outside, metres(wall.length, wall.length_sigma));
    return;
  }
  double solid_from = 0;
  for (const auto& opening : wall.openings) {
    const double from = std::clamp(opening.start, solid_from, length);
    const double to = std::clamp(opening.start + opening.width, from, length);
    if (from > solid_from) write_line(dxf, dw, a + along * solid_from, a + along * from, kWallLayer, kWallColour);
    write_line(dxf, dw, a + along * from, a + along * to, kOpeningLayer, kOpeningColour);
    char label[48];
    std::snprintf(label, sizeof(label), "opening %.2f m", to - from);
    write_text(dxf, dw, a + along * ((from + to) / 2) - outside * 2 * kTextHeight, label);
    solid_from = to;
  }
  if (solid_from < length) write_line(dxf, dw, a + along * solid_from, b, kWallLayer, kWallColour);

  write_dimension(dxf, dw, a, b, outside, metres(wall.length, wall.length_sigma));
}

void write_room(DL_Dxf& dxf, DL_WriterA& dw, const RoomResult& room, const std::string& title) {
  const size_t count = room.corners.size();
  const bool closed = room.status == room_measurement::RoomStatus::Ok && count == room.walls.size() && count >= 3;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero(), low = Eigen::Vector2d::Zero();
  if (closed) {
    for (size_t w = 0; w < count; ++w) {
      write_wall(dxf, dw, room.walls[w], room.corners[w], room.corners[(w + 1) % count]);
      centre += room.corners[w] / static_cast<double>(count);
      low = low.cwiseMin(room.corners[w]);
    }
  } else {
    for (const auto& wall : room.candidates) {
      const Eigen::Vector2d base = wall.normal * wall.offset;
      write_line(dxf, dw, base + wall.direction() * wall.start, base + wall.direction() * wall.end, kWallLayer,
                 kWallColour);
      low = low.cwiseMin(base + wall.direction() * wall.start).cwiseMin(base + wall.direction() * wall.end);
    }
  }
  char summary[160];
  if (closed) {
    write_text(dxf, dw, centre, "floor area " + metres(room.area, room.area_sigma, "m2", 2));
    if (room.ceiling_height()) {
      std::snprintf(summary, sizeof(summary), "ceiling height %.2f m", *room.ceiling_height());
      write_text(dxf, dw, centre - Eigen::Vector2d(0, 2 * kTextHeight), summary);
    }
  } else {
    std::snprintf(summary, sizeof(summary), "not measured: %s: %.100s (candidate walls)",
                  room_measurement::status_name(room.status), room.message.c_str());
    write_text(dxf, dw, Eigen::Vector2d(0, -4 * kTextHeight), summary);
  }
  write_text(dxf, dw, low - Eigen::Vector2d(0, 1.0), title + " (metres, scanner at 0,0)");
}

}  // namespace

void write_dxf_plan(const std::string& path, const RoomResult& room, const std::string& title) {
  DL_Dxf dxf;
  std::unique_ptr<DL_WriterA> dw(dxf.out(path.c_str(), DL_Codes::AC1015));
  if (!dw) throw DxfPlanError(path + ": cannot open for writing");
  write_preamble(dxf, *dw);
  dw->sectionEntities();
  write_room(dxf, *dw, room, title);
  dw->sectionEnd();
  dxf.writeObjects(*dw);
  dxf.writeObjectsEnd(*dw);
  dw->dxfEOF();
  dw->close();
}

}  // namespace scanbus::room_plan
