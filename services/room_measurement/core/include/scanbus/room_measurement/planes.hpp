// PCL's part of the pipeline: VoxelGrid and RANSAC planes. Only planes.cpp includes PCL.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace scanbus::room_measurement {

struct VoxelResult {
  std::vector<Eigen::Vector3f> points;
  bool overflow = false;  // the grid would exceed 32-bit indices: PCL would return the input as is
};

VoxelResult voxel_grid(const std::vector<Eigen::Vector3f>& points, double leaf);

struct RansacSettings {
  double distance = 0.04;      // m
  double eps_angle_deg = 2.0;  // against the axis constraint
  int iterations = 1000;
  size_t min_inliers = 50;
  int max_planes = 20;
};

struct Plane {
  Eigen::Vector4d coefficients;  // a x + b y + c z + d = 0, unit normal, input frame
  std::vector<Eigen::Vector3f> inliers;
};

// Planes one after another, each from what the previous ones left. Vertical planes
// (parallel to z) or horizontal ones (perpendicular to z). The cloud is centred first:
// PCL's RANSAC is unstable far from the origin.
std::vector<Plane> extract_planes(const std::vector<Eigen::Vector3f>& points, bool vertical,
                                  const RansacSettings& settings);

}  // namespace scanbus::room_measurement
