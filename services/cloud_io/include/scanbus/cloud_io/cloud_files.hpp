// Cloud files a person or another tool opens: PCD, PLY and XYZ text read (hardened against
// damaged files: tests/fuzz, cloud_file), PCD written (PCL, CloudCompare, RViz via pcl_ros).
// Only the .cpp includes PCL.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "scanbus/cloud_point.hpp"

namespace scanbus::cloud_io {

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

}  // namespace scanbus::cloud_io
