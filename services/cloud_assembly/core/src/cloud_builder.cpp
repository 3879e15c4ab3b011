#include "scanbus/cloud_assembly/cloud_builder.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace scanbus::cloud_assembly {

std::vector<Eigen::Vector3d> scan_points(const sensor::LaserScan& scan, const sensor::RangeGate& gate) {
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector2d& p : sensor::kept_points(scan, gate)) points.emplace_back(p.x(), p.y(), 0.0);
  return points;
}

ContinuousCloud::ContinuousCloud(double voxel_size, size_t max_voxels)
    : voxel_size_(voxel_size), max_voxels_(max_voxels) {
  if (!(voxel_size > 0)) throw std::invalid_argument("voxel size must be positive");
}

void ContinuousCloud::add(const std::vector<Eigen::Vector3d>& points) {
  // 21 bits a coordinate: +-1048576 voxels, 21 km at 2 cm; further points are dropped.
  constexpr int64_t kHalf = 1 << 20;
  for (const auto& p : points) {
    const Eigen::Vector3d cell = (p / voxel_size_).array().floor();
    if (!p.allFinite() || (cell.array().abs() >= kHalf).any()) {
      ++dropped_;
      continue;
    }
    const uint64_t key = (static_cast<uint64_t>(static_cast<int64_t>(cell.x()) + kHalf) << 42) |
                         (static_cast<uint64_t>(static_cast<int64_t>(cell.y()) + kHalf) << 21) |
                         static_cast<uint64_t>(static_cast<int64_t>(cell.z()) + kHalf);
    auto found = voxels_.find(key);
    if (found == voxels_.end()) {
      if (voxels_.size() >= max_voxels_) {
        ++dropped_;
        continue;
      }
      found = voxels_.emplace(key, Voxel{}).first;
    }
    found->second.sum += p;
    ++found->second.count;
  }
}

std::vector<Eigen::Vector3f> ContinuousCloud::points() const {
  std::vector<Eigen::Vector3f> result;
  result.reserve(voxels_.size());
  for (const auto& [key, voxel] : voxels_) result.push_back((voxel.sum / voxel.count).cast<float>());
  return result;
}

ScanWindow::ScanWindow(double max_age, size_t max_points) : max_age_(max_age), max_points_(max_points) {}

void ScanWindow::add(double stamp, std::vector<Eigen::Vector3f> points) {
  const auto later =
      std::upper_bound(scans_.begin(), scans_.end(), stamp, [](double t, const auto& scan) { return t < scan.first; });
  points_ += points.size();
  scans_.insert(later, {stamp, std::move(points)});
  while (!scans_.empty() && (scans_.back().first - scans_.front().first > max_age_ || points_ > max_points_)) {
    points_ -= scans_.front().second.size();
    scans_.pop_front();
  }
}

std::vector<Eigen::Vector3f> ScanWindow::assemble(double begin, double end) const {
  std::vector<Eigen::Vector3f> result;
  for (const auto& [stamp, points] : scans_)
    if (stamp >= begin && stamp <= end) result.insert(result.end(), points.begin(), points.end());
  return result;
}

}  // namespace scanbus::cloud_assembly
