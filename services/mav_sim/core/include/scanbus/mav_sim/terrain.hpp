// Ground that is not flat: a height field of simple features added together (a slope,
// mounds and ditches, steps, rough ground), for the MAV simulator's world. Map frame, z up,
// metres. Heights are the world's truth; nothing here knows what the fusion assumes.
#pragma once

#include <Eigen/Core>

#include <cmath>

#include <optional>
#include <string>
#include <vector>

namespace scanbus {
class Config;
}

namespace scanbus::mav_sim {

// A raised-cosine bump: `height` at the centre, 0 from `radius` out; a negative height is a ditch.
struct Mound {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 1, height = 0.3;  // m
};

// The ground rises by `height` across the line through `at` whose normal points at
// `direction` (rad from x), over a ramp `width` wide (a kerb, a terrace edge).
struct Step {
  Eigen::Vector2d at = Eigen::Vector2d::Zero();
  double direction = 0;               // rad
  double height = 0.2, width = 0.02;  // m

  // Signed distance of (x, y) across the step's line, towards where the ground is higher.
  double across(const Eigen::Vector2d& xy) const {
    return Eigen::Vector2d(std::cos(direction), std::sin(direction)).dot(xy - at);
  }
};

struct Terrain {
  Eigen::Vector2d slope = Eigen::Vector2d::Zero();  // dz/dx, dz/dy: a plane through z = 0 at the origin
  std::vector<Mound> mounds;
  std::vector<Step> steps;
  double roughness = 0;               // m RMS of rough ground (grass, gravel, ploughed soil)
  double roughness_wavelength = 0.5;  // m, its typical wavelength
  unsigned roughness_seed = 1;

  bool flat() const;
};

// The terrain's surface, ready to be sampled and hit by rays (its rough ground drawn once).
// The map origin is on the ground where the flight starts (a MAV log's META origin says so):
// the features are lowered or raised together so that, without the rough ground, they pass
// through z = 0 there, also when a step's high side or a mound covers the origin.
class TerrainSurface {
 public:
  explicit TerrainSurface(Terrain terrain = {});

  double height_at(const Eigen::Vector2d& xy) const;
  // Distance along the unit `direction` from `origin` to the ground, or +inf within `range`
  // (also from under the ground).
  double cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double range = 1000) const;
  const Terrain& terrain() const { return terrain_; }

 private:
  double relief(const Eigen::Vector2d& xy) const;  // slope, mounds and steps as the file gives them

  struct Wave {
    Eigen::Vector2d k;  // rad/m
    double phase = 0, amplitude = 0;
  };
  Terrain terrain_;
  std::vector<Wave> waves_;
  double origin_relief_ = 0;  // m, relief() at the origin: taken off every height
  double max_gradient_ = 0;   // an upper bound of |gradient|: how far a ray may step without passing through
};

// What is wrong with a terrain, if anything: slopes up to 45 degrees, at most 100 mounds and 100
// steps, mound radii 0.05-1000 m,
// heights within 100 m, step ramps 1 mm-100 m wide, roughness up to 1 m RMS, wavelengths
// 0.05-100 m. `key` names the feature as the YAML file does ("mounds[1].radius").
struct TerrainProblem {
  std::string key, what;
  std::string message() const { return key + " " + what; }
};
std::optional<TerrainProblem> terrain_problem(const Terrain& terrain);

// A terrain from the `terrain` map of a YAML file (docs/mav_simulator.md): slope, mounds,
// steps, roughness, roughness_wavelength, seed. Throws ConfigError naming the key.
Terrain terrain_from_config(const Config& section);

// The terrain of a YAML file's `terrain` map (config/terrain/); throws ConfigError naming the
// file and what is wrong in it, also a key nobody reads.
Terrain load_terrain(const std::string& path);

}  // namespace scanbus::mav_sim
