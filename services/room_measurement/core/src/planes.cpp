#include "scanbus/room_measurement/planes.hpp"

#include <pcl/console/print.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace scanbus::room_measurement {

namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& shift) {
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(points.size());
  for (const auto& point : points)
    cloud->push_back(pcl::PointXYZ(point.x() - shift.x(), point.y() - shift.y(), point.z() - shift.z()));
  return cloud;
}

}  // namespace

VoxelResult voxel_grid(const std::vector<Eigen::Vector3f>& points, double leaf) {
  VoxelResult result;
  if (points.empty()) return result;
  Eigen::Vector3f low = points.front(), high = low;
  for (const auto& point : points) {
    low = low.cwiseMin(point);
    high = high.cwiseMax(point);
  }
  // The check PCL makes internally before giving up silently.
  const Eigen::Array3d cells = ((high - low).cast<double>().array() / leaf).floor() + 1;
  if (cells.prod() > static_cast<double>(std::numeric_limits<int32_t>::max())) {
    result.overflow = true;
    result.points = points;
    return result;
  }
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(to_pcl(points, Eigen::Vector3f::Zero()));
  grid.setLeafSize(static_cast<float>(leaf), static_cast<float>(leaf), static_cast<float>(leaf));
  pcl::PointCloud<pcl::PointXYZ> out;
  grid.filter(out);
  result.points.reserve(out.size());
  for (const auto& point : out) result.points.emplace_back(point.x, point.y, point.z);
  return result;
}

std::vector<Plane> extract_planes(const std::vector<Eigen::Vector3f>& points, bool vertical,
                                  const RansacSettings& settings) {
  std::vector<Plane> planes;
  if (points.size() < settings.min_inliers) return planes;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  for (const auto& point : points) centre += point;
  centre /= static_cast<float>(points.size());
  auto remaining = to_pcl(points, centre);

  // PCL reports "no model found" on stderr; it is an expected end of the loop here.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  pcl::SACSegmentation<pcl::PointXYZ> segmentation;
  segmentation.setOptimizeCoefficients(true);
  segmentation.setModelType(vertical ? pcl::SACMODEL_PARALLEL_PLANE : pcl::SACMODEL_PERPENDICULAR_PLANE);
  segmentation.setMethodType(pcl::SAC_RANSAC);
  segmentation.setAxis(Eigen::Vector3f::UnitZ());                   // must be a unit vector
  segmentation.setEpsAngle(settings.eps_angle_deg * M_PI / 180.0);  // 0 would disable the constraint
  segmentation.setDistanceThreshold(settings.distance);
  segmentation.setMaxIterations(settings.iterations);

  while (static_cast<int>(planes.size()) < settings.max_planes && remaining->size() >= settings.min_inliers) {
    pcl::PointIndices inliers;
    pcl::ModelCoefficients coefficients;
    segmentation.setInputCloud(remaining);
    segmentation.segment(inliers, coefficients);
    // "No solution found" leaves both empty: never index into them then.
    if (inliers.indices.size() < settings.min_inliers || coefficients.values.size() != 4) break;
    Plane plane;
    const Eigen::Vector3d normal(coefficients.values[0], coefficients.values[1], coefficients.values[2]);
    const double norm = normal.norm();
    // Back to the input frame: n.(p - c) + d = 0  ->  n.p + (d - n.c) = 0.
    plane.coefficients << normal / norm, (coefficients.values[3] - normal.dot(centre.cast<double>())) / norm;
    std::vector<bool> used(remaining->size(), false);
    for (int index : inliers.indices) {
      used[index] = true;
      const auto& p = (*remaining)[index];
      plane.inliers.emplace_back(p.x + centre.x(), p.y + centre.y(), p.z + centre.z());
    }
    auto rest = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    rest->reserve(remaining->size() - inliers.indices.size());
    for (size_t i = 0; i < remaining->size(); ++i)
      if (!used[i]) rest->push_back((*remaining)[i]);
    remaining = rest;
    planes.push_back(std::move(plane));
  }
  return planes;
}

}  // namespace scanbus::room_measurement
