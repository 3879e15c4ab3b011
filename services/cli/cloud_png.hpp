// A height-coloured view of a cloud as PNG (cairo), for a person to look at.
#pragma once

#include <string>
#include <vector>

#include "scanbus/cloud_point.hpp"

namespace scanbus::cli {

// The cloud from above (x right, y up) or from the side (x right, z up), points coloured by
// height, 1 m grid, optionally the origin marked as the scanner. Throws on failure.
enum class CloudView { Top, Side };
void write_cloud_png(const std::string& path, const std::vector<CloudPoint>& points, const std::string& title,
                     CloudView view, bool mark_origin);

}  // namespace scanbus::cli
