// Files a person opens: the cloud as PCD (PCL, CloudCompare, RViz via pcl_ros) and a
// height-coloured top view as PNG. Only this file's .cpp includes PCL.
#pragma once

#include <string>
#include <vector>

#include "scanbus/point_cloud.hpp"

namespace scanbus::cli {

// Binary PCD, fields x y z intensity. Throws std::runtime_error naming the path.
void write_pcd(const std::string& path, const std::vector<CloudPoint>& points);

// Top view (x right, y up), points coloured by height, 1 m grid. Throws on failure.
void write_top_view_png(const std::string& path, const std::vector<CloudPoint>& points, const std::string& title);

}  // namespace scanbus::cli
