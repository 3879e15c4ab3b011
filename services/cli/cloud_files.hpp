// Files a person opens: the cloud as PCD (PCL, CloudCompare, RViz via pcl_ros) and a
// height-coloured view as PNG. Only this file's .cpp includes PCL.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "scanbus/point_cloud.hpp"

namespace scanbus::cli {

// Binary PCD, fields x y z intensity. Throws std::runtime_error naming the path.
void write_pcd(const std::string& path, const std::vector<CloudPoint>& points);

// PCD, PLY or XYZ text (x y z per line, more columns ignored), by extension, scaled by
// `scale` to metres. Non-finite points are kept (the caller counts and drops them).
// Throws CloudFileError naming the file and the problem.
class CloudFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
std::vector<Eigen::Vector3f> read_cloud(const std::string& path, double scale);
// Metres per unit of a cloud file's coordinates: "m", "cm" or "mm" (the --unit options).
double metres_per_unit(const std::string& unit);

// The cloud from above (x right, y up) or from the side (x right, z up), points coloured by
// height, 1 m grid, optionally the origin marked as the scanner. Throws on failure.
enum class CloudView { Top, Side };
void write_cloud_png(const std::string& path, const std::vector<CloudPoint>& points, const std::string& title,
                     CloudView view, bool mark_origin);

}  // namespace scanbus::cli
