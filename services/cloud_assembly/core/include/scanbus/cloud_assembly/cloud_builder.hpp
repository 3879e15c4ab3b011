// The MAV paper's two ways to build the ground cloud from laser scans and transforms:
// a continuous builder that accumulates every scan (here in a voxel map, so memory stays
// bounded however long the flight), and a window of recent scans from which the cloud of
// any time span is assembled on request, like ROS's laser_assembler.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <deque>
#include <unordered_map>
#include <vector>

#include "scanbus/sensor/laser_scan.hpp"

namespace scanbus::cloud_assembly {

// The scan's kept returns (sensor::kept_points) in the laser frame, z = 0.
std::vector<Eigen::Vector3d> scan_points(const sensor::LaserScan& scan, const sensor::RangeGate& gate);

// Every point ever added, one per voxel (the mean of the points that fell in it), up to a
// budget of voxels; points that would start a voxel past the budget are counted and dropped.
class ContinuousCloud {
 public:
  ContinuousCloud(double voxel_size, size_t max_voxels);
  void add(const std::vector<Eigen::Vector3d>& points);
  std::vector<Eigen::Vector3f> points() const;
  size_t size() const { return voxels_.size(); }
  uint64_t dropped() const { return dropped_; }
  double voxel_size() const { return voxel_size_; }

 private:
  struct Voxel {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    uint32_t count = 0;
  };
  double voxel_size_;
  size_t max_voxels_;
  std::unordered_map<uint64_t, Voxel> voxels_;
  uint64_t dropped_ = 0;
};

// The latest scans (map-frame points by stamp), kept for `max_age` s behind the newest and
// at most `max_points` points in all, oldest dropped first.
class ScanWindow {
 public:
  ScanWindow(double max_age, size_t max_points);
  void add(double stamp, std::vector<Eigen::Vector3f> points);
  // The points of every scan stamped in [begin, end].
  std::vector<Eigen::Vector3f> assemble(double begin, double end) const;
  double oldest() const { return scans_.empty() ? 0 : scans_.front().first; }
  double newest() const { return scans_.empty() ? 0 : scans_.back().first; }
  size_t scans() const { return scans_.size(); }

 private:
  double max_age_;
  size_t max_points_, points_ = 0;
  std::deque<std::pair<double, std::vector<Eigen::Vector3f>>> scans_;  // by stamp
};

}  // namespace scanbus::cloud_assembly
