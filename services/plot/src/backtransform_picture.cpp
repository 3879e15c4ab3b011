#include "scanbus/plot/backtransform_picture.hpp"

#include "scanbus/plot/canvas.hpp"

namespace scanbus::plot {

namespace {

// The laser's x axis up the picture and y to the left, as a person looks along it.
std::vector<Eigen::Vector2d> as_seen(const std::vector<Eigen::Vector2d>& points) {
  std::vector<Eigen::Vector2d> picture;
  for (const auto& p : points) picture.emplace_back(-p.y(), p.x());
  return picture;
}

}  // namespace

void write_backtransform_picture(const std::string& path, const std::vector<Eigen::Vector2d>& reference,
                                 const std::vector<Eigen::Vector2d>& backtransformed, const std::string& title,
                                 const std::string& summary) {
  const auto scan_n = as_seen(reference), scan_n1 = as_seen(backtransformed);
  Eigen::Vector2d low(0, 0), high(0, 0);  // the laser is always in view
  for (const auto* points : {&scan_n, &scan_n1})
    for (const auto& p : *points) low = low.cwiseMin(p), high = high.cwiseMax(p);
  Canvas canvas(path, low, high);
  canvas.dots(scan_n, 2.5, {0.15, 0.35, 0.85});  // scan N: blue, larger
  canvas.dots(scan_n1, 1.3, {0.9, 0.2, 0.15});   // scan N+1 carried back: red, on top
  canvas.ring({0, 0}, 5, Colour::grey(0));
  canvas.heading(title, summary);
  canvas.legend("blue = scan N, red = scan N+1 back-transformed by the match, circle = laser, x up");
  canvas.save();
}

}  // namespace scanbus::plot
