// A room to scan: a floor plan polygon of vertical walls between a floor and a ceiling,
// with the scanner at the origin. Ray casting gives the range a LiDAR would measure.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace scanbus::sim {

struct RoomModel {
  std::vector<Eigen::Vector2d> corners;  // floor plan, counter-clockwise, scanner frame, m
  double floor_z = -1.2;                 // m, below the scanner
  double ceiling_z = 1.3;                // m, above the scanner

  // The built-in demo room: 5.2 m x 3.9 m, 2.5 m high, turned 20 degrees against the
  // scanner's axes, scanner off-centre at 1.2 m above the floor.
  static RoomModel built_in();

  // Distance along the unit direction to the first surface; nullopt when the ray escapes.
  std::optional<double> cast(const Eigen::Vector3d& direction) const;

  std::vector<double> wall_lengths() const;
  double floor_area() const;
};

}  // namespace scanbus::sim
