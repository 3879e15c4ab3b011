// Packing points into sensor_msgs/PointCloud2 (x y z intensity, float32, little endian,
// the layout RViz2 and Foxglove read directly) and reading x y z back from any cloud.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "scanbus/cloud_point.hpp"
#include "scanbus_msgs/PointCloud2.h"

namespace scanbus {

// `fourth_field` names what CloudPoint::intensity carries (e.g. "stdev" for an elevation grid).
sensor_msgs::msg::PointCloud2 to_point_cloud2(const std::vector<CloudPoint>& points, const std::string& frame_id,
                                              const builtin_interfaces::msg::Time& stamp,
                                              const char* fourth_field = "intensity");

// x y z rgb (rgb as PCL packs it: 0x00RRGGBB in the bytes of a float32), the layout RViz2
// and Foxglove colour by. `colours` has one entry per point.
sensor_msgs::msg::PointCloud2 to_coloured_point_cloud2(const std::vector<Eigen::Vector3f>& points,
                                                       const std::vector<uint32_t>& colours,
                                                       const std::string& frame_id,
                                                       const builtin_interfaces::msg::Time& stamp);

// Throws std::invalid_argument naming what is wrong (missing x/y/z, not float32, short data).
std::vector<CloudPoint> from_point_cloud2(const sensor_msgs::msg::PointCloud2& cloud);

}  // namespace scanbus
