#include "backtransform_plot.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace scanbus::cli {

void write_backtransform_plot(const std::string& path, const std::vector<Eigen::Vector2d>& reference,
                              const std::vector<Eigen::Vector2d>& backtransformed, const std::string& title,
                              const std::string& summary) {
  const int size = 800, margin = 60;
  Eigen::Vector2d low(0, 0), high(0, 0);  // the laser is always in view
  for (const auto* points : {&reference, &backtransformed})
    for (const auto& p : *points) low = low.cwiseMin(p), high = high.cwiseMax(p);
  const double span = std::max({high.x() - low.x(), high.y() - low.y(), 1.0});
  const double scale = (size - 2 * margin) / span;
  // The laser's x axis points up the picture, y to the left, as a person looks along it.
  auto px = [&](const Eigen::Vector2d& p) { return size - margin - (p.y() - low.y()) * scale; };
  auto py = [&](const Eigen::Vector2d& p) { return size - margin - (p.x() - low.x()) * scale; };
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, size, size);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  auto draw = [&](const std::vector<Eigen::Vector2d>& points, double r, double g, double b, double radius) {
    cairo_set_source_rgb(cr, r, g, b);
    for (const auto& p : points) cairo_arc(cr, px(p), py(p), radius, 0, 2 * M_PI), cairo_fill(cr);
  };
  draw(reference, 0.15, 0.35, 0.85, 2.5);      // scan N: blue, larger
  draw(backtransformed, 0.9, 0.2, 0.15, 1.3);  // scan N+1 carried back: red, on top
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_arc(cr, px({0, 0}), py({0, 0}), 5, 0, 2 * M_PI);
  cairo_stroke(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 16);
  cairo_move_to(cr, margin, 28);
  cairo_show_text(cr, title.c_str());
  cairo_set_font_size(cr, 12);
  cairo_move_to(cr, margin, 48);
  cairo_show_text(cr, summary.c_str());
  cairo_move_to(cr, margin, size - 20);
  cairo_show_text(cr, "blue = scan N, red = scan N+1 back-transformed by the match, circle = laser, x up");
  cairo_destroy(cr);
  cairo_status_t status = cairo_surface_write_to_png(surface, path.c_str());
  if (status == CAIRO_STATUS_SUCCESS) status = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(path + ": cannot write: " + cairo_status_to_string(status));
}

}  // namespace scanbus::cli
