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
  double base = 0;                                 // m: its footprint's height (GroundWorld sets it)
};

class GroundWorld {
 public:
  // Each box stands on the terrain at its centre: on a slope its uphill edge is buried and its
  // downhill edge stands off the ground by the slope times half its length (1.6 cm for 0.6 m on 3 degrees).
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
