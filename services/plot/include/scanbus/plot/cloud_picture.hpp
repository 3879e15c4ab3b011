// A height-coloured view of a cloud (PNG, or SVG by the file's extension), for a person to look at.
#pragma once

#include <string>
#include <vector>

#include "scanbus/cloud_point.hpp"

namespace scanbus::plot {

// The cloud from above (x right, y up) or from the side (x right, z up), points coloured by
// height, 1 m grid, optionally the origin marked as the scanner. Throws std::runtime_error
// naming the file when there is nothing to draw or it cannot be written.
enum class CloudView { Top, Side };
void write_cloud_picture(const std::string& path, const std::vector<CloudPoint>& points, const std::string& title,
                         CloudView view, bool mark_origin);

}  // namespace scanbus::plot
