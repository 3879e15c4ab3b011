#include "scanbus/plot/canvas.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace scanbus::plot {

namespace {

constexpr double kMinFont = 9;

bool ends_with(const std::string& text, const std::string& tail) {
  return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

// `text` with each byte that does not start a valid UTF-8 sequence replaced by '?': cairo
// refuses invalid text by putting the context in error, and a Latin-1 file name in a title
// must not cost the picture. (Nothing packaged beside cairo does this; glib is not linked.)
std::string valid_utf8(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    const size_t length = byte < 0x80           ? 1
                          : (byte >> 5) == 0x6  ? 2
                          : (byte >> 4) == 0xE  ? 3
                          : (byte >> 3) == 0x1E ? 4
                                                : 0;
    bool valid = length > 0 && i + length <= text.size();
    for (size_t k = 1; valid && k < length; ++k) valid = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
    out += valid ? text.substr(i, length) : "?";
    i += valid ? length : 1;
  }
  return out;
}

void set(cairo_t* cr, const Colour& colour) {
  cairo_set_source_rgba(cr, colour.red, colour.green, colour.blue, colour.alpha);
}

}  // namespace

Colour Colour::hex(uint32_t rgb, double alpha) {
  return {((rgb >> 16) & 0xFF) / 255.0, ((rgb >> 8) & 0xFF) / 255.0, (rgb & 0xFF) / 255.0, alpha};
}

Canvas::Canvas(std::string path, const Eigen::Vector2d& low, const Eigen::Vector2d& high, const Layout& layout)
    : path_(std::move(path)), svg_(ends_with(path_, ".svg")), low_(low), high_(high), margin_(layout.margin) {
  const Eigen::Vector2d extent = (high_ - low_).cwiseMax(1e-3);
  const int inside = layout.size - 2 * layout.margin;
  if (layout.square) {
    scale_ = inside / std::max({extent.x(), extent.y(), 1.0});
    width_ = height_ = layout.size;
  } else {
    scale_ = inside / extent.maxCoeff();
    width_ = static_cast<int>(extent.x() * scale_) + 2 * layout.margin;
    height_ = static_cast<int>(extent.y() * scale_) + 2 * layout.margin;
  }
  width_ = std::max(width_, layout.min_width);
  height_ = std::max(height_, layout.min_height);
  // The box in the middle of the room left for it (a square picture of a long box).
  centring_ = ((Eigen::Array2d(width_, height_) - 2.0 * margin_ - extent.array() * scale_) / 2).max(0.0).matrix();
  surface_ = svg_ ? cairo_svg_surface_create(path_.c_str(), width_, height_)
                  : cairo_image_surface_create(CAIRO_FORMAT_RGB24, width_, height_);
  cr_ = cairo_create(surface_);
  cairo_set_source_rgb(cr_, 1, 1, 1);
  cairo_paint(cr_);
  cairo_select_font_face(cr_, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
}

Canvas::~Canvas() {
  if (!cr_) return;
  cairo_destroy(cr_);
  cairo_surface_destroy(surface_);
  if (svg_) std::remove(path_.c_str());  // never saved (an error on the way): no half picture left
}

cairo_t* Canvas::context() const {
  if (!cr_) throw std::logic_error(path_ + ": the picture is already saved");
  return cr_;
}

Eigen::Vector2d Canvas::pixel(const Eigen::Vector2d& world) const {
  return {margin_ + centring_.x() + (world.x() - low_.x()) * scale_,
          height_ - margin_ - centring_.y() - (world.y() - low_.y()) * scale_};
}

bool Canvas::contains(const Eigen::Vector2d& world) const {
  return (world.array() >= low_.array()).all() && (world.array() <= high_.array()).all();
}

void Canvas::grid(double step, const Colour& colour) {
  cairo_t* cr = context();
  set(cr, colour);
  cairo_set_line_width(cr, 1);
  const Eigen::Vector2d corner_low = pixel(low_), corner_high = pixel(high_);
  for (double x = std::ceil(low_.x() / step) * step; x <= high_.x(); x += step) {
    cairo_move_to(cr, pixel({x, 0}).x(), corner_low.y());
    cairo_line_to(cr, pixel({x, 0}).x(), corner_high.y());
  }
  for (double y = std::ceil(low_.y() / step) * step; y <= high_.y(); y += step) {
    cairo_move_to(cr, corner_low.x(), pixel({0, y}).y());
    cairo_line_to(cr, corner_high.x(), pixel({0, y}).y());
  }
  cairo_stroke(cr);
}

void Canvas::dot(const Eigen::Vector2d& at, double radius, const Colour& colour) {
  cairo_t* cr = context();
  set(cr, colour);
  const Eigen::Vector2d p = pixel(at);
  cairo_new_sub_path(cr);
  cairo_arc(cr, p.x(), p.y(), radius, 0, 2 * M_PI);
  cairo_fill(cr);
}

void Canvas::dots(const std::vector<Eigen::Vector2d>& at, double radius, const Colour& colour) {
  cairo_t* cr = context();
  set(cr, colour);
  for (const auto& point : at) {
    const Eigen::Vector2d p = pixel(point);
    cairo_new_sub_path(cr);
    cairo_arc(cr, p.x(), p.y(), radius, 0, 2 * M_PI);
  }
  cairo_fill(cr);
}

void Canvas::squares(const std::vector<Eigen::Vector2d>& at, double side, const Colour& colour) {
  cairo_t* cr = context();
  set(cr, colour);
  for (const auto& point : at) {
    const Eigen::Vector2d p = pixel(point);
    cairo_rectangle(cr, p.x() - side / 2, p.y() - side / 2, side, side);
  }
  cairo_fill(cr);
}

void Canvas::ring(const Eigen::Vector2d& at, double radius, const Colour& colour, double width) {
  cairo_t* cr = context();
  set(cr, colour);
  cairo_set_line_width(cr, width);
  const Eigen::Vector2d p = pixel(at);
  cairo_new_sub_path(cr);
  cairo_arc(cr, p.x(), p.y(), radius, 0, 2 * M_PI);
  cairo_stroke(cr);
}

void Canvas::line(const Eigen::Vector2d& from, const Eigen::Vector2d& to, const Colour& colour, double width,
                  bool dashed) {
  cairo_t* cr = context();
  set(cr, colour);
  cairo_set_line_width(cr, width);
  const double dash[] = {8, 6};
  cairo_set_dash(cr, dash, dashed ? 2 : 0, 0);
  const Eigen::Vector2d a = pixel(from), b = pixel(to);
  cairo_move_to(cr, a.x(), a.y());
  cairo_line_to(cr, b.x(), b.y());
  cairo_stroke(cr);
  cairo_set_dash(cr, dash, 0, 0);
}

void Canvas::clip_to_box() {
  cairo_t* cr = context();
  const Eigen::Vector2d a = pixel(low_), b = pixel(high_);
  cairo_rectangle(cr, a.x(), b.y(), b.x() - a.x(), a.y() - b.y());
  cairo_clip(cr);
}

void Canvas::unclip() { cairo_reset_clip(context()); }

Eigen::Vector2d Canvas::text_size(const std::string& text, double font) const {
  cairo_t* cr = context();
  cairo_set_font_size(cr, font);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, valid_utf8(text).c_str(), &extents);
  return {extents.width, extents.height};
}

void Canvas::text(const Eigen::Vector2d& at, const std::string& text, double font, const Colour& colour) {
  cairo_t* cr = context();
  set(cr, colour);
  cairo_set_font_size(cr, font);
  cairo_move_to(cr, at.x(), at.y());
  cairo_show_text(cr, valid_utf8(text).c_str());
}

void Canvas::fitted_text(const Eigen::Vector2d& at, const std::string& text, double font) {
  const double room = width_ - at.x() - 8;
  std::string shown = valid_utf8(text);
  while (font > kMinFont && text_size(shown, font).x() > room) font -= 0.5;
  if (text_size(shown, font).x() > room) {
    while (!shown.empty() && text_size(shown + "\u2026", font).x() > room) {
      // One UTF-8 character off the end: its continuation bytes, then its first byte.
      while (!shown.empty() && (static_cast<unsigned char>(shown.back()) & 0xC0) == 0x80) shown.pop_back();
      if (!shown.empty()) shown.pop_back();
    }
    shown += "\u2026";
  }
  this->text(at, shown, font, Colour::grey(0));
}

void Canvas::heading(const std::string& title, const std::string& subtitle) {
  fitted_text({margin_, 28}, title, 16);
  if (!subtitle.empty()) fitted_text({margin_, 48}, subtitle, 12);
}

void Canvas::legend(const std::string& text) { fitted_text({margin_, height_ - 20.0}, text, 12); }

void Canvas::save() {
  // A context in error (a failed drawing call) has dropped what came after it.
  cairo_status_t status = cairo_status(context());
  cairo_destroy(cr_);
  cr_ = nullptr;
  if (status == CAIRO_STATUS_SUCCESS && !svg_) status = cairo_surface_write_to_png(surface_, path_.c_str());
  cairo_surface_finish(surface_);
  if (status == CAIRO_STATUS_SUCCESS) status = cairo_surface_status(surface_);
  cairo_surface_destroy(surface_);
  surface_ = nullptr;
  if (status != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(path_ + ": cannot write: " + cairo_status_to_string(status));
}

}  // namespace scanbus::plot
