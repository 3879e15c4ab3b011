// The ground under the MAV: a terrain (flat at z = 0 unless given) with boxes standing on
// it (map frame, z up), and the laser's rays cast into it.
#pragma once

#include <Eigen/Geometry>

#include <optional>
#include <vector>

#include "scanbus/mav_sim/terrain.hpp"

namespace scanbus::mav_sim {

struct Box {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double yaw = 0;                                  // rad, about z
  Eigen::Vector3d size = Eigen::Vector3d::Ones();  // length (along its x), width, height; m
  double base = 0;                                 // m: the ground's height at its centre (GroundWorld sets it)
  double bottom = 0;  // m: the lowest ground under its footprint, where its sides reach down to (GroundWorld sets it)
};

class GroundWorld {
 public:
  // Each box's top lies its height above the terrain at its centre, and its sides reach down to
  // the lowest ground under its footprint: on a slope or across a step its uphill part is buried
  // and no ray passes under its downhill edge (scenario III's 8 m block on a 5 % slope would
  // otherwise stand 0.2 m off the ground at one end, and the ground seen under it be scored as its top).
  // Throws std::invalid_argument for a box whose sizes are not positive and finite.
  explicit GroundWorld(std::vector<Box> boxes = {}, Terrain terrain = {});

  // Distance along the unit `direction` from `origin` to the first surface, or +inf.
  double cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;
  // Height of the surface at (x, y).
  double height_at(const Eigen::Vector2d& xy) const;
  // The height where a cloud point's height error means something: none within `margin` of
  // a box's edge or a step's ramp, where a few centimetres across decide between two heights.
  std::optional<double> scored_height(const Eigen::Vector2d& xy, double margin) const;
  const std::vector<Box>& boxes() const { return boxes_; }
  const TerrainSurface& terrain() const { return terrain_; }

 private:
  std::vector<Box> boxes_;
  TerrainSurface terrain_;
};

}  // namespace scanbus::mav_sim
