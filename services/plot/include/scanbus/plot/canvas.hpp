// One picture of a plane for a person to look at (cairo): a world box in metres mapped to
// pixels, a grid, marks, lines and text, and the title and legend every scanbus picture has.
// The floor plan, the height-coloured cloud and the backtransform pair are drawn with it.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

typedef struct _cairo cairo_t;
typedef struct _cairo_surface cairo_surface_t;

namespace scanbus::plot {

// Channels 0..1, alpha 1 = opaque.
struct Colour {
  double red = 0, green = 0, blue = 0, alpha = 1;
  static Colour hex(uint32_t rgb, double alpha = 1);  // 0xRRGGBB
  static Colour grey(double level) { return {level, level, level, 1}; }
};

// How the world box becomes a picture.
struct Layout {
  int size = 800;      // px: the square picture's side, or a fitted picture's longer side
  int margin = 60;     // px between the box and the picture's edges
  bool square = true;  // square (plans); else the shorter side fits the box's shape
  int min_width = 0;   // px, at least (a fitted picture of a long thin box keeps room for text)
  int min_height = 0;
};

class Canvas {
 public:
  // The world box low..high (m; x right, y up) on a white picture, written by save() to
  // `path`: SVG when it ends in .svg, PNG otherwise.
  Canvas(std::string path, const Eigen::Vector2d& low, const Eigen::Vector2d& high, const Layout& layout = {});
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  Eigen::Vector2d pixel(const Eigen::Vector2d& world) const;
  double scale() const { return scale_; }  // px per m
  int width() const { return width_; }
  int height() const { return height_; }
  // Inside the world box given at construction.
  bool contains(const Eigen::Vector2d& world) const;

  // Lines every `step` m across the box.
  void grid(double step = 1, const Colour& colour = Colour::grey(0.88));
  // Filled circles of `radius` px; `dots` fills them as one path (one colour, many points).
  void dot(const Eigen::Vector2d& at, double radius, const Colour& colour);
  void dots(const std::vector<Eigen::Vector2d>& at, double radius, const Colour& colour);
  // Filled squares of `side` px: the fastest mark for many points.
  void squares(const std::vector<Eigen::Vector2d>& at, double side, const Colour& colour);
  // A circle's outline, `radius` and `width` in px.
  void ring(const Eigen::Vector2d& at, double radius, const Colour& colour, double width = 2);
  void line(const Eigen::Vector2d& from, const Eigen::Vector2d& to, const Colour& colour, double width,
            bool dashed = false);
  // Marks outside the box are cut off until unclip().
  void clip_to_box();
  void unclip();

  // Text: its size in px, and drawn with its left end of the baseline at `pixel`.
  Eigen::Vector2d text_size(const std::string& text, double font) const;
  void text(const Eigen::Vector2d& pixel, const std::string& text, double font,
            const Colour& colour = Colour::grey(0.1));
  // The title (and a line under it) above the box, the legend under it; text too long for
  // the picture is set smaller, down to 9 px, then cut with an ellipsis.
  void heading(const std::string& title, const std::string& subtitle = "");
  void legend(const std::string& text);

  // Writes the file and ends the picture (drawing after it throws std::logic_error); throws
  // std::runtime_error naming the file when it cannot be written or the drawing failed. A
  // picture never saved leaves no file.
  void save();

 private:
  cairo_t* context() const;
  void fitted_text(const Eigen::Vector2d& pixel, const std::string& text, double font);

  std::string path_;
  bool svg_;
  Eigen::Vector2d low_, high_;
  int width_ = 0, height_ = 0, margin_ = 0;
  double scale_ = 1;
  Eigen::Vector2d centring_ = Eigen::Vector2d::Zero();  // px
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
};

}  // namespace scanbus::plot
