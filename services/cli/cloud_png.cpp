#include "cloud_png.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scanbus/cloud_assembly/cloud_builder.hpp"

namespace scanbus::cli {

void write_cloud_png(const std::string& path, const std::vector<CloudPoint>& points, const std::string& title,
                     CloudView view, bool mark_origin) {
  if (points.empty()) throw std::runtime_error(path + ": no points to draw");
  // Robust extent: a few far returns (through doors, windows) must not shrink the picture.
  Eigen::Vector3f low, high;
  double colour_low = 0, colour_high = 0;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<float> values;
    for (const auto& point : points) values.push_back(point.position[axis]);
    std::sort(values.begin(), values.end());
    low[axis] = values[values.size() * 2 / 100] - 0.5f;
    high[axis] = values[values.size() * 98 / 100] + 0.5f;
    // Colours span nearly all heights: small raised things (boxes on a field) must show.
    if (axis == 2) colour_low = values[values.size() / 100], colour_high = values[values.size() * 999 / 1000];
  }
  // Picture axes: x right; y (top view) or z (side view, looking along +y) up.
  const bool top = view == CloudView::Top;
  const int up = top ? 1 : 2, depth = top ? 2 : 1;
  // 800 pixels wide (or high, when the cloud is taller than wide); the other side fits it.
  const int size = 800, margin = 40;
  const double span = std::max({high.x() - low.x(), high[up] - low[up], 1e-3f});
  const double scale = (size - 2 * margin) / span;
  const int width = static_cast<int>((high.x() - low.x()) * scale) + 2 * margin;
  const int height = std::max(240, static_cast<int>((high[up] - low[up]) * scale) + 2 * margin);
  auto px = [&](double x) { return margin + (x - low.x()) * scale; };
  auto py = [&](double v) { return height - margin - (v - low[up]) * scale; };

  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, std::max(width, 640), height);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
  cairo_set_line_width(cr, 1);
  for (double x = std::ceil(low.x()); x <= high.x(); x += 1.0) {
    cairo_move_to(cr, px(x), margin);
    cairo_line_to(cr, px(x), height - margin);
  }
  for (double v = std::ceil(low[up]); v <= high[up]; v += 1.0) {
    cairo_move_to(cr, margin, py(v));
    cairo_line_to(cr, width - margin, py(v));
  }
  cairo_stroke(cr);
  // The points nearest the viewer drawn last: the highest from above, the lowest y from the side.
  std::vector<const CloudPoint*> order;
  for (const auto& point : points) order.push_back(&point);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) {
    return top ? a->position[depth] < b->position[depth] : a->position[depth] > b->position[depth];
  });
  cairo_rectangle(cr, margin, margin, width - 2 * margin, height - 2 * margin);
  cairo_clip(cr);
  for (const CloudPoint* point : order) {
    const uint32_t colour = cloud_assembly::height_colour(point->position.z(), colour_low, colour_high);
    cairo_set_source_rgb(cr, (colour >> 16) / 255.0, ((colour >> 8) & 0xFF) / 255.0, (colour & 0xFF) / 255.0);
    cairo_arc(cr, px(point->position.x()), py(point->position[up]), 1.6, 0, 2 * M_PI);
    cairo_fill(cr);
  }
  cairo_reset_clip(cr);
  std::string legend = top ? "top view" : "side view (x right, z up)";
  legend += ", grid 1 m, colour = height (blue low, red high)";
  if (mark_origin) {
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_arc(cr, px(0), py(0), 4, 0, 2 * M_PI);
    cairo_fill(cr);
    legend += ", black dot = scanner";
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 14);
  cairo_move_to(cr, margin, 25);
  cairo_show_text(cr, title.c_str());
  cairo_move_to(cr, margin, height - 12);
  cairo_show_text(cr, legend.c_str());
  cairo_destroy(cr);
  const cairo_status_t status = cairo_surface_write_to_png(surface, path.c_str());
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(path + ": cannot write PNG: " + cairo_status_to_string(status));
}

}  // namespace scanbus::cli
