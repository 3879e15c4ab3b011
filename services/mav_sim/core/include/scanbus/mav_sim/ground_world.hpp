// The ground under the MAV: a plane at z = 0 with boxes standing on it (map frame, z up),
// and the laser's rays cast into it.
#pragma once

#include <Eigen/Geometry>

#include <vector>

namespace scanbus::mav_sim {

struct Box {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double yaw = 0;                                 // rad, about z
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  // length (along its x), width, height; m
};

class GroundWorld {
 public:
  explicit GroundWorld(std::vector<Box> boxes = {}) : boxes_(std::move(boxes)) {}

  // Distance along the unit `direction` from `origin` to the first surface, or +inf.
  double cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;
  // Height of the surface at (x, y).
  double height_at(const Eigen::Vector2d& xy) const;
  const std::vector<Box>& boxes() const { return boxes_; }

 private:
  std::vector<Box> boxes_;
};

}  // namespace scanbus::mav_sim
