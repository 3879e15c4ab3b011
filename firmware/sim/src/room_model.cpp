#include "scanbus/sim/room_model.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

namespace scanbus::sim {

RoomModel RoomModel::built_in() {
  RoomModel room;
  const double angle = 20.0 * M_PI / 180.0;
  const Eigen::Rotation2Dd turn(angle);
  const Eigen::Vector2d offset(-1.9, -1.4);  // scanner stands 1.9 m and 1.4 m from two walls
  for (const Eigen::Vector2d& corner : {Eigen::Vector2d(0, 0), Eigen::Vector2d(5.2, 0), Eigen::Vector2d(5.2, 3.9),
                                       Eigen::Vector2d(0, 3.9)})
    room.corners.push_back(turn * (corner + offset));
  room.floor_z = -1.2;
  room.ceiling_z = 1.3;
  return room;
}

std::optional<double> RoomModel::cast(const Eigen::Vector3d& direction) const {
  double nearest = std::numeric_limits<double>::infinity();
  if (direction.z() < 0) nearest = floor_z / direction.z();
  if (direction.z() > 0) nearest = ceiling_z / direction.z();
  const Eigen::Vector2d ray = direction.head<2>();
  for (size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector2d a = corners[i];
    const Eigen::Vector2d edge = corners[(i + 1) % corners.size()] - a;
    // Solve t * ray = a + s * edge for the wall's vertical plane.
    const double denominator = ray.x() * edge.y() - ray.y() * edge.x();
    if (std::abs(denominator) < 1e-12) continue;
    const double t = (a.x() * edge.y() - a.y() * edge.x()) / denominator;
    const double s = (a.x() * ray.y() - a.y() * ray.x()) / denominator;
    if (t > 0 && s >= 0 && s <= 1 && t < nearest) nearest = t;
  }
  if (!std::isfinite(nearest)) return std::nullopt;
  return nearest;
}

std::vector<double> RoomModel::wall_lengths() const {
  std::vector<double> lengths;
  for (size_t i = 0; i < corners.size(); ++i) lengths.push_back((corners[(i + 1) % corners.size()] - corners[i]).norm());
  return lengths;
}

double RoomModel::floor_area() const {
  double twice = 0;  // shoelace
  for (size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector2d& a = corners[i];
    const Eigen::Vector2d& b = corners[(i + 1) % corners.size()];
    twice += a.x() * b.y() - b.x() * a.y();
  }
  return std::abs(twice) / 2;
}

}  // namespace scanbus::sim
