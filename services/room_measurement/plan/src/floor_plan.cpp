#include "scanbus/room_plan/floor_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scanbus/palette.hpp"
#include "scanbus/plot/canvas.hpp"
#include "scanbus/room_plan/dxf_plan.hpp"

namespace scanbus::room_plan {

namespace {

using plot::Canvas;
using plot::Colour;
using room_measurement::RoomResult;
using room_measurement::RoomStatus;
using room_measurement::WallLine;

std::vector<Eigen::Vector2d> top_view(const std::vector<Eigen::Vector3f>& points) {
  std::vector<Eigen::Vector2d> view;
  for (const auto& p : points) view.push_back(p.head<2>().cast<double>());
  return view;
}

// A measured room shows its walls; one that did not close shows every candidate, to see why.
std::vector<WallLine> shown_walls(const RoomResult& room) {
  if (room.status != RoomStatus::Ok) return room.candidates;
  std::vector<WallLine> shown;
  for (const auto& wall : room.walls) shown.push_back(wall.line);
  return shown;
}

// A label centred off the wall at `at` by its own size: inside the room (side -1) or outside
// (+1) of the wall's outward normal n, kept on the page.
void wall_label(Canvas& canvas, const std::string& text, const Eigen::Vector2d& at, const Eigen::Vector2d& n,
                double font, int side) {
  const Eigen::Vector2d size = canvas.text_size(text, font);
  const double clearance = std::abs(n.x()) * size.x() / 2 + std::abs(n.y()) * size.y() / 2 + 8;
  const Eigen::Vector2d centre = canvas.pixel(at + side * n * (clearance / canvas.scale()));
  const double left = std::clamp(centre.x() - size.x() / 2, 2.0, canvas.width() - size.x() - 2);
  canvas.text({left, centre.y() + size.y() / 2}, text, font);
}

// Openings (doors, windows seen through) as white gaps with a thin outline of the wall.
void draw_openings(Canvas& canvas, const room_measurement::MeasuredWall& wall, const Eigen::Vector2d& a,
                   const Eigen::Vector2d& b, const Colour& colour) {
  const Eigen::Vector2d along = (b - a).normalized();
  for (const auto& opening : wall.openings) {
    const Eigen::Vector2d from = a + along * opening.start, to = from + along * opening.width;
    canvas.line(from, to, Colour::grey(1), 5);
    canvas.line(from, to, colour, 1);
    char width[32];
    std::snprintf(width, sizeof(width), "opening %.2f m", opening.width);
    wall_label(canvas, width, (from + to) / 2, wall.line.normal, 11, +1);  // the length is inside
  }
}

void draw_walls(Canvas& canvas, const RoomResult& room) {
  const size_t count = room.corners.size();
  if (count != room.walls.size()) return;
  for (size_t w = 0; w < count; ++w) {  // corner to corner
    const Eigen::Vector2d a = room.corners[w], b = room.corners[(w + 1) % count];
    const Colour colour = Colour::hex(wall_colour(w));
    canvas.line(a, b, colour, 3, room.walls[w].inferred());  // a wall not seen, inferred: dashed
    draw_openings(canvas, room.walls[w], a, b, colour);
    // Length and its one sigma just inside the room, off the wall's middle by its own size.
    char label[64];
    if (room.walls[w].length_sigma > 0)
      std::snprintf(label, sizeof(label), "%.3f \u00b1 %.3f m", room.walls[w].length, room.walls[w].length_sigma);
    else
      std::snprintf(label, sizeof(label), "%.3f m", room.walls[w].length);
    wall_label(canvas, label, (a + b) / 2, room.walls[w].line.normal, 15, -1);
  }
}

std::string summary_of(const RoomResult& room) {
  if (room.status != RoomStatus::Ok) return "not measured: " + room.message + " (candidate walls shown)";
  char summary[160];
  char area_sigma[32] = "";
  if (room.area_sigma > 0) std::snprintf(area_sigma, sizeof(area_sigma), " \u00b1 %.2f", room.area_sigma);
  std::snprintf(summary, sizeof(summary), "%zu walls, floor area %.2f%s m2, perimeter %.2f m", room.walls.size(),
                room.area, area_sigma, room.perimeter);
  std::string text = summary;
  if (room.ceiling_height()) {
    std::snprintf(summary, sizeof(summary), ", ceiling %.2f m", *room.ceiling_height());
    return text + summary;
  }
  return text + ", no ceiling height";
}

void write_picture(const std::string& path, const RoomResult& room, const std::string& title,
                   const std::vector<Eigen::Vector3f>& background) {
  const std::vector<WallLine> shown = shown_walls(room);
  Eigen::Vector2d low(0, 0), high(0, 0);  // the scanner is always in view
  for (const auto& corner : room.corners) low = low.cwiseMin(corner), high = high.cwiseMax(corner);
  for (const auto& wall : shown)
    for (const auto& p : top_view(wall.inliers)) low = low.cwiseMin(p), high = high.cwiseMax(p);
  Canvas canvas(path, low, high);
  canvas.grid();
  std::vector<Eigen::Vector2d> scan;
  for (const auto& p : top_view(background))
    if (canvas.contains(p)) scan.push_back(p);
  canvas.squares(scan, 1.5, Colour::grey(0.78));
  for (size_t w = 0; w < shown.size(); ++w) {
    canvas.squares(top_view(shown[w].inliers), 2, Colour::hex(wall_colour(w), 0.35));  // inliers, faint
    if (room.status == RoomStatus::Ok) continue;
    const Eigen::Vector2d base = shown[w].normal * shown[w].offset;
    canvas.line(base + shown[w].direction() * shown[w].start, base + shown[w].direction() * shown[w].end,
                Colour::hex(wall_colour(w)), 2);
  }
  draw_walls(canvas, room);
  for (size_t i = 0; i < room.corners.size(); ++i) {  // measured corners filled, inferred ones open
    const bool inferred = i < room.corner_inferred.size() && room.corner_inferred[i];
    inferred ? canvas.ring(room.corners[i], 4, Colour::grey(0), 1) : canvas.dot(room.corners[i], 4, Colour::grey(0));
  }
  canvas.ring({0, 0}, 5, Colour::grey(0));  // the scanner
  canvas.heading(title, summary_of(room));
  canvas.legend(std::string("floor plan, grid 1 m, circle = scanner, dots = corners (open: inferred), ") +
                "dashed = wall not seen, white gaps = openings, " +
                (background.empty() ? "faint = wall inliers" : "grey = scan (top view)"));
  canvas.save();
}

}  // namespace

void write_floor_plan(const std::string& path, const RoomResult& room, const std::string& title,
                      const std::vector<Eigen::Vector3f>& background) {
  if (path.size() > 4 && path.compare(path.size() - 4, 4, ".dxf") == 0) return write_dxf_plan(path, room, title);
  write_picture(path, room, title, background);
}

}  // namespace scanbus::room_plan
