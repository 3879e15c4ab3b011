#include "floor_plan.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "scanbus/room_measurement/room_message.hpp"
#include "scanbus/room_plan/dxf_plan.hpp"

namespace scanbus::cli {

void write_floor_plan(const std::string& path, const room_measurement::RoomResult& room, const std::string& title,
                      const std::vector<Eigen::Vector3f>& background) {
  auto ends_with = [&](const char* extension) {
    return path.size() > 4 && path.compare(path.size() - 4, 4, extension) == 0;
  };
  if (ends_with(".dxf")) return room_plan::write_dxf_plan(path, room, title);
  const bool svg = ends_with(".svg");
  const int size = 800, margin = 60;
  Eigen::Vector2d low(0, 0), high(0, 0);  // the scanner is always in view
  for (const auto& corner : room.corners) {
    low = low.cwiseMin(corner);
    high = high.cwiseMax(corner);
  }
  // A measured room shows its walls; one that did not close shows every candidate, to see why.
  std::vector<room_measurement::WallLine> shown;
  for (const auto& wall : room.walls) shown.push_back(wall.line);
  if (room.status != room_measurement::RoomStatus::Ok) shown = room.candidates;
  for (const auto& wall : shown)
    for (const auto& p : wall.inliers) {
      low = low.cwiseMin(p.head<2>().cast<double>());
      high = high.cwiseMax(p.head<2>().cast<double>());
    }
  const double span = std::max({high.x() - low.x(), high.y() - low.y(), 1.0});
  const double scale = (size - 2 * margin) / span;
  auto px = [&](double x) { return margin + (x - low.x()) * scale; };
  auto py = [&](double y) { return size - margin - (y - low.y()) * scale; };

  cairo_surface_t* surface = svg ? cairo_svg_surface_create(path.c_str(), size, size)
                                 : cairo_image_surface_create(CAIRO_FORMAT_RGB24, size, size);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
  cairo_set_line_width(cr, 1);
  for (double x = std::ceil(low.x()); x <= high.x(); x += 1)
    cairo_move_to(cr, px(x), margin), cairo_line_to(cr, px(x), size - margin);
  for (double y = std::ceil(low.y()); y <= high.y(); y += 1)
    cairo_move_to(cr, margin, py(y)), cairo_line_to(cr, size - margin, py(y));
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0.78, 0.78, 0.78);
  for (const auto& p : background)
    if (p.x() >= low.x() && p.x() <= high.x() && p.y() >= low.y() && p.y() <= high.y())
      cairo_rectangle(cr, px(p.x()) - 0.75, py(p.y()) - 0.75, 1.5, 1.5);
  cairo_fill(cr);
  auto set_colour = [&](uint32_t rgb, double alpha) {
    cairo_set_source_rgba(cr, ((rgb >> 16) & 0xFF) / 255.0, ((rgb >> 8) & 0xFF) / 255.0, (rgb & 0xFF) / 255.0, alpha);
  };
  for (size_t w = 0; w < shown.size(); ++w) {  // inliers, faint
    set_colour(room_measurement::wall_colour(w), 0.35);
    for (const auto& p : shown[w].inliers) cairo_rectangle(cr, px(p.x()) - 1, py(p.y()) - 1, 2, 2);
    cairo_fill(cr);
    if (room.status == room_measurement::RoomStatus::Ok) continue;
    const Eigen::Vector2d a = shown[w].normal * shown[w].offset + shown[w].direction() * shown[w].start;
    const Eigen::Vector2d b = shown[w].normal * shown[w].offset + shown[w].direction() * shown[w].end;
    set_colour(room_measurement::wall_colour(w), 1);
    cairo_set_line_width(cr, 2);
    cairo_move_to(cr, px(a.x()), py(a.y()));
    cairo_line_to(cr, px(b.x()), py(b.y()));
    cairo_stroke(cr);
  }
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  // A label centred off the wall at `at` by its own size: inside the room (side -1) or outside
  // (+1) of the wall's outward normal n.
  auto show_label = [&](const char* text, const Eigen::Vector2d& at, const Eigen::Vector2d& n, double font, int side) {
    cairo_set_font_size(cr, font);
    cairo_text_extents_t extents;
    cairo_text_extents(cr, text, &extents);
    const double clearance = std::abs(n.x()) * extents.width / 2 + std::abs(n.y()) * extents.height / 2 + 8;
    const Eigen::Vector2d centre = at + side * n * (clearance / scale);
    const double left = std::clamp(px(centre.x()) - extents.width / 2, 2.0, size - extents.width - 2);  // on the page
    cairo_move_to(cr, left, py(centre.y()) + extents.height / 2);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_show_text(cr, text);
  };
  const size_t count = room.corners.size();
  for (size_t w = 0; w < room.walls.size() && count == room.walls.size(); ++w) {  // walls corner to corner
    const Eigen::Vector2d a = room.corners[w], b = room.corners[(w + 1) % count];
    set_colour(room_measurement::wall_colour(w), 1);
    cairo_set_line_width(cr, 3);
    const double dash[] = {8, 6};
    cairo_set_dash(cr, dash, room.walls[w].inferred() ? 2 : 0, 0);  // a wall not seen, inferred: dashed
    cairo_move_to(cr, px(a.x()), py(a.y()));
    cairo_line_to(cr, px(b.x()), py(b.y()));
    cairo_stroke(cr);
    cairo_set_dash(cr, dash, 0, 0);
    // Openings (doors, windows seen through) as white gaps with a thin outline of the wall.
    const Eigen::Vector2d along = (b - a).normalized();
    for (const auto& opening : room.walls[w].openings) {
      const Eigen::Vector2d from = a + along * opening.start, to = from + along * opening.width;
      cairo_set_source_rgb(cr, 1, 1, 1);
      cairo_set_line_width(cr, 5);
      cairo_move_to(cr, px(from.x()), py(from.y()));
      cairo_line_to(cr, px(to.x()), py(to.y()));
      cairo_stroke(cr);
      set_colour(room_measurement::wall_colour(w), 1);
      cairo_set_line_width(cr, 1);
      cairo_move_to(cr, px(from.x()), py(from.y()));
      cairo_line_to(cr, px(to.x()), py(to.y()));
      cairo_stroke(cr);
      char width[32];
      std::snprintf(width, sizeof(width), "opening %.2f m", opening.width);
      show_label(width, (from + to) / 2, room.walls[w].line.normal, 11, +1);  // the length is inside
    }
    // Length and its one sigma just inside the room, off the wall's middle by its own size.
    char label[64];
    if (room.walls[w].length_sigma > 0)
      std::snprintf(label, sizeof(label), "%.3f \u00b1 %.3f m", room.walls[w].length, room.walls[w].length_sigma);
    else
      std::snprintf(label, sizeof(label), "%.3f m", room.walls[w].length);
    show_label(label, (a + b) / 2, room.walls[w].line.normal, 15, -1);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  for (size_t i = 0; i < room.corners.size(); ++i) {  // measured corners filled, inferred ones open
    cairo_new_sub_path(cr);
    cairo_arc(cr, px(room.corners[i].x()), py(room.corners[i].y()), 4, 0, 2 * M_PI);
    const bool inferred = i < room.corner_inferred.size() && room.corner_inferred[i];
    inferred ? cairo_stroke(cr) : cairo_fill(cr);
  }
  cairo_arc(cr, px(0), py(0), 5, 0, 2 * M_PI);  // the scanner
  cairo_stroke(cr);
  cairo_set_font_size(cr, 16);
  cairo_move_to(cr, margin, 28);
  cairo_show_text(cr, title.c_str());
  char summary[160];
  if (room.status == room_measurement::RoomStatus::Ok) {
    char area_sigma[32] = "";
    if (room.area_sigma > 0) std::snprintf(area_sigma, sizeof(area_sigma), " \u00b1 %.2f", room.area_sigma);
    std::snprintf(summary, sizeof(summary), "%zu walls, floor area %.2f%s m2, perimeter %.2f m%s", room.walls.size(),
                  room.area, area_sigma, room.perimeter, room.ceiling_height() ? "" : ", no ceiling height");
    if (room.ceiling_height())
      std::snprintf(summary + std::strlen(summary), sizeof(summary) - std::strlen(summary), ", ceiling %.2f m",
                    *room.ceiling_height());
  } else {
    std::snprintf(summary, sizeof(summary), "not measured: %.100s (candidate walls shown)", room.message.c_str());
  }
  cairo_set_font_size(cr, 12);
  cairo_move_to(cr, margin, 48);
  cairo_show_text(cr, summary);
  cairo_move_to(cr, margin, size - 20);
  cairo_show_text(cr, background.empty() ? "floor plan, grid 1 m, circle = scanner, dots = corners (open: inferred), "
                                           "dashed = wall not seen, white gaps = openings, faint = wall inliers"
                                         : "floor plan, grid 1 m, circle = scanner, dots = corners (open: inferred), "
                                           "dashed = wall not seen, white gaps = openings, grey = scan (top view)");
  cairo_destroy(cr);
  cairo_status_t status = CAIRO_STATUS_SUCCESS;
  if (!svg) status = cairo_surface_write_to_png(surface, path.c_str());
  cairo_surface_finish(surface);
  if (status == CAIRO_STATUS_SUCCESS) status = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(path + ": cannot write: " + cairo_status_to_string(status));
}

}  // namespace scanbus::cli
