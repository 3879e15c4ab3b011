#include "scanbus/plot/cloud_picture.hpp"

#include <algorithm>
#include <stdexcept>

#include "scanbus/palette.hpp"
#include "scanbus/plot/canvas.hpp"

namespace scanbus::plot {

void write_cloud_picture(const std::string& path, const std::vector<CloudPoint>& points, const std::string& title,
                         CloudView view, bool mark_origin) {
  if (points.empty()) throw std::runtime_error(path + ": no points to draw");
  // Robust extent: a few far returns (through doors, windows) must not shrink the picture.
  Eigen::Vector3d low, high;
  double colour_low = 0, colour_high = 0;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<float> values;
    for (const auto& point : points) values.push_back(point.position[axis]);
    std::sort(values.begin(), values.end());
    low[axis] = values[values.size() * 2 / 100] - 0.5;
    high[axis] = values[values.size() * 98 / 100] + 0.5;
    // Colours span nearly all heights: small raised things (boxes on a field) must show.
    if (axis == 2) colour_low = values[values.size() / 100], colour_high = values[values.size() * 999 / 1000];
  }
  // Picture axes: x right; y (top view) or z (side view, looking along +y) up.
  const bool top = view == CloudView::Top;
  const int up = top ? 1 : 2, depth = top ? 2 : 1;
  Layout layout;
  layout.margin = 40;
  layout.square = false;
  layout.min_width = 640;  // the legend's room
  layout.min_height = 240;
  Canvas canvas(path, {low.x(), low[up]}, {high.x(), high[up]}, layout);
  canvas.grid(1, Colour::grey(0.85));
  // The points nearest the viewer drawn last: the highest from above, the lowest y from the side.
  std::vector<const CloudPoint*> order;
  for (const auto& point : points) order.push_back(&point);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) {
    return top ? a->position[depth] < b->position[depth] : a->position[depth] > b->position[depth];
  });
  canvas.clip_to_box();
  for (const CloudPoint* point : order)
    canvas.dot({point->position.x(), point->position[up]}, 1.6,
               Colour::hex(height_colour(point->position.z(), colour_low, colour_high)));
  canvas.unclip();
  std::string legend = top ? "top view" : "side view (x right, z up)";
  legend += ", grid 1 m, colour = height (blue low, red high)";
  if (mark_origin) {
    canvas.dot({0, 0}, 4, Colour::grey(0));
    legend += ", black dot = scanner";
  }
  canvas.heading(title);
  canvas.legend(legend);
  canvas.save();
}

}  // namespace scanbus::plot
