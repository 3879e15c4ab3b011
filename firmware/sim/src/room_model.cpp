#include "scanbus/sim/room_model.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace scanbus::sim {

namespace {

Eigen::Matrix3d heading_rotation(double heading) {
  return Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).matrix();
}

// Ray-box slab test; distance to the entry point, or infinity.
double cast_box(const Box& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  double near = 0, far = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(direction[axis]) < 1e-12) {
      if (origin[axis] < box.min[axis] || origin[axis] > box.max[axis]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double t0 = (box.min[axis] - origin[axis]) / direction[axis];
    double t1 = (box.max[axis] - origin[axis]) / direction[axis];
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
    if (near > far) return std::numeric_limits<double>::infinity();
  }
  return near > 0 ? near : std::numeric_limits<double>::infinity();
}

double distance_to_box(const Box& box, const Eigen::Vector3d& point) {
  const Eigen::Vector3d outside = (box.min - point).cwiseMax(point - box.max).cwiseMax(0.0);
  if (outside.squaredNorm() > 0) return outside.norm();
  return ((point - box.min).cwiseMin(box.max - point)).minCoeff();  // inside: to the nearest face
}

}  // namespace

Eigen::Vector3d RoomModel::to_room(const Eigen::Vector3d& scanner_point) const {
  return scanner + heading_rotation(heading) * scanner_point;
}

std::optional<double> RoomModel::cast(const Eigen::Vector3d& scanner_origin,
                                      const Eigen::Vector3d& scanner_direction) const {
  const Eigen::Vector3d direction = heading_rotation(heading) * scanner_direction;
  const Eigen::Vector3d origin = to_room(scanner_origin);
  double nearest = std::numeric_limits<double>::infinity();
  if (direction.z() < 0) nearest = -origin.z() / direction.z();
  if (direction.z() > 0) nearest = (ceiling - origin.z()) / direction.z();
  if (std::isfinite(nearest) && !within_reach((origin + nearest * direction).head<2>()))
    nearest = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector2d a = corners[i] - origin.head<2>();
    const Eigen::Vector2d edge = corners[(i + 1) % corners.size()] - corners[i];
    const double denominator = direction.x() * edge.y() - direction.y() * edge.x();
    if (std::abs(denominator) < 1e-12) continue;
    const double t = (a.x() * edge.y() - a.y() * edge.x()) / denominator;
    const double s = (a.x() * direction.y() - a.y() * direction.x()) / denominator;
    if (t <= 0 || s < 0 || s > 1 || t >= nearest) continue;
    const double along = s * edge.norm(), height = origin.z() + t * direction.z();
    bool through_opening = false;
    for (const auto& opening : openings)
      through_opening |= opening.wall == i && along >= opening.from && along <= opening.to &&
                         height >= opening.bottom && height <= opening.top;
    if (!through_opening) nearest = t;
  }
  for (const auto& wall : outside_walls) {
    const Eigen::Vector2d a = wall.from - origin.head<2>(), edge = wall.to - wall.from;
    const double denominator = direction.x() * edge.y() - direction.y() * edge.x();
    if (std::abs(denominator) < 1e-12) continue;
    const double t = (a.x() * edge.y() - a.y() * edge.x()) / denominator;
    const double s = (a.x() * direction.y() - a.y() * direction.x()) / denominator;
    const double height = origin.z() + t * direction.z();
    if (t > 0 && s >= 0 && s <= 1 && t < nearest && height >= 0 && height <= ceiling) nearest = t;
  }
  for (const auto& box : boxes) nearest = std::min(nearest, cast_box(box, origin, direction));
  if (!std::isfinite(nearest)) return std::nullopt;
  return nearest;
}

double RoomModel::distance_to_surface(const Eigen::Vector3d& scanner_point) const {
  const Eigen::Vector3d point = to_room(scanner_point);
  double best = std::min(std::abs(point.z()), std::abs(point.z() - ceiling));
  for (size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector2d a = corners[i], b = corners[(i + 1) % corners.size()];
    const Eigen::Vector2d edge = b - a;
    const double s = std::clamp((point.head<2>() - a).dot(edge) / edge.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (point.head<2>() - (a + s * edge)).norm());
  }
  for (const auto& box : boxes) best = std::min(best, distance_to_box(box, point));
  return best;
}

bool RoomModel::within_reach(const Eigen::Vector2d& point) const {
  Eigen::Vector2d low = corners.front(), high = low;
  for (const auto& corner : corners) {
    low = low.cwiseMin(corner);
    high = high.cwiseMax(corner);
  }
  return (point.array() >= low.array() - outside).all() && (point.array() <= high.array() + outside).all();
}

std::vector<double> RoomModel::wall_lengths() const {
  std::vector<double> lengths;
  for (size_t i = 0; i < corners.size(); ++i)
    lengths.push_back((corners[(i + 1) % corners.size()] - corners[i]).norm());
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

void RoomModel::validate() const {
  if (corners.size() < 3) throw std::invalid_argument("a room needs at least 3 corners");
  bool inside = false;  // even-odd rule
  for (size_t i = 0, j = corners.size() - 1; i < corners.size(); j = i++) {
    const Eigen::Vector2d& a = corners[i];
    const Eigen::Vector2d& b = corners[j];
    if ((a.y() > scanner.y()) != (b.y() > scanner.y()) &&
        scanner.x() < (b.x() - a.x()) * (scanner.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  if (!inside) throw std::invalid_argument("the scanner stands outside the floor plan");
  if (scanner.z() <= 0 || scanner.z() >= ceiling)
    throw std::invalid_argument("the scanner is not between floor and ceiling");
  const auto lengths = wall_lengths();
  for (const auto& opening : openings) {
    if (opening.wall >= corners.size())
      throw std::invalid_argument("an opening names wall " + std::to_string(opening.wall) + ", which does not exist");
    if (opening.from < 0 || opening.to > lengths[opening.wall] || opening.from >= opening.to)
      throw std::invalid_argument("an opening on wall " + std::to_string(opening.wall) + " does not fit the wall");
  }
}

}  // namespace scanbus::sim
