#include "scanbus/mav_sim/ground_world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace scanbus::mav_sim {

namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

// Slab test in the box's own frame (origin at its footprint's centre on the ground).
double cast_box(const Box& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  const Eigen::Matrix3d to_box = Eigen::AngleAxisd(-box.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d o = to_box * (origin - Eigen::Vector3d(box.centre.x(), box.centre.y(), box.base));
  const Eigen::Vector3d d = to_box * direction;
  const Eigen::Vector3d low(-box.size.x() / 2, -box.size.y() / 2, box.bottom - box.base),
      high(box.size.x() / 2, box.size.y() / 2, box.size.z());
  double near = 0, far = kNone;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(d[axis]) < 1e-12) {
      if (o[axis] < low[axis] || o[axis] > high[axis]) return kNone;
      continue;
    }
    double t1 = (low[axis] - o[axis]) / d[axis], t2 = (high[axis] - o[axis]) / d[axis];
    if (t1 > t2) std::swap(t1, t2);
    near = std::max(near, t1);
    far = std::min(far, t2);
    if (near > far) return kNone;
  }
  return near > 0 ? near : kNone;
}

// Sampled every 2 cm (coarser over boxes beyond 40 m): ground that dips between two samples
// leaves a gap that deep under the box's edge, a millimetre or two on the rough ground of
// config/terrain; never above the ground at the centre.
double lowest_ground_under(const Box& box, const TerrainSurface& terrain) {
  const Eigen::Rotation2Dd to_map(box.yaw);
  const auto samples = [](double size) { return static_cast<int>(std::clamp(std::ceil(size / 0.02), 1.0, 2000.0)); };
  const int nx = samples(box.size.x()), ny = samples(box.size.y());
  double lowest = box.base;
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      const Eigen::Vector2d local(box.size.x() * (double(i) / nx - 0.5), box.size.y() * (double(j) / ny - 0.5));
      lowest = std::min(lowest, terrain.height_at(box.centre + to_map * local));
    }
  }
  return lowest;
}

}  // namespace

GroundWorld::GroundWorld(std::vector<Box> boxes, Terrain terrain)
    : boxes_(std::move(boxes)), terrain_(std::move(terrain)) {
  for (Box& box : boxes_) {
    if (!((box.size.array() > 0) && box.size.array().isFinite()).all())
      throw std::invalid_argument("a box's sizes must be positive and finite");
    box.base = terrain_.height_at(box.centre);
    box.bottom = lowest_ground_under(box, terrain_);
  }
}

double GroundWorld::cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const {
  double nearest = terrain_.cast(origin, direction);
  for (const Box& box : boxes_) nearest = std::min(nearest, cast_box(box, origin, direction));
  return nearest;
}

double GroundWorld::height_at(const Eigen::Vector2d& xy) const {
  double top = terrain_.height_at(xy);
  const Eigen::Vector3d above(xy.x(), xy.y(), 1000), down = -Eigen::Vector3d::UnitZ();
  for (const Box& box : boxes_) top = std::max(top, 1000 - cast_box(box, above, down));
  return top;
}

std::optional<double> GroundWorld::scored_height(const Eigen::Vector2d& xy, double margin) const {
  for (const Box& box : boxes_) {
    const Eigen::Vector2d local = Eigen::Rotation2Dd(-box.yaw) * (xy - box.centre);
    const Eigen::Vector2d half = box.size.head<2>() / 2;
    const Eigen::Vector2d outside = local.cwiseAbs() - half;  // per axis, > 0 outside the footprint
    const double distance = outside.maxCoeff() > 0 ? outside.cwiseMax(0).norm() : -outside.maxCoeff();
    if (distance < margin) return std::nullopt;
  }
  for (const Step& step : terrain_.terrain().steps) {
    if (std::abs(step.across(xy)) < step.width / 2 + margin) return std::nullopt;
  }
  return height_at(xy);
}

}  // namespace scanbus::mav_sim
