#include "scanbus/mav_sim/terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "scanbus/config.hpp"

namespace scanbus::mav_sim {

namespace {

double ramp(double s, double width) { return std::clamp(s / width + 0.5, 0.0, 1.0); }

}  // namespace

bool Terrain::flat() const { return slope.isZero() && mounds.empty() && steps.empty() && roughness <= 0; }

// Rough ground as a few plane waves of random direction, wavelength and phase: smooth, so a
// ray meets it once, and with a bounded gradient; their amplitude sets the RMS.
TerrainSurface::TerrainSurface(Terrain terrain) : terrain_(std::move(terrain)) {
  constexpr int kWaves = 8;
  origin_relief_ = relief(Eigen::Vector2d::Zero());
  max_gradient_ = terrain_.slope.norm();
  for (const Mound& m : terrain_.mounds) max_gradient_ += std::abs(m.height) * M_PI / (2 * m.radius);
  for (const Step& s : terrain_.steps) max_gradient_ += std::abs(s.height) / s.width;
  if (terrain_.roughness <= 0) return;
  std::mt19937 random(terrain_.roughness_seed);
  std::uniform_real_distribution<double> unit(0, 1);
  const double amplitude = terrain_.roughness * std::sqrt(2.0 / kWaves);  // the RMS of a sum of sines
  for (int i = 0; i < kWaves; ++i) {
    const double angle = 2 * M_PI * unit(random);
    const double wavelength = terrain_.roughness_wavelength * (0.5 + unit(random));
    const Eigen::Vector2d k = Eigen::Vector2d(std::cos(angle), std::sin(angle)) * (2 * M_PI / wavelength);
    waves_.push_back({k, 2 * M_PI * unit(random), amplitude});
    max_gradient_ += amplitude * k.norm();
  }
}

double TerrainSurface::relief(const Eigen::Vector2d& xy) const {
  double z = terrain_.slope.dot(xy);
  for (const Mound& m : terrain_.mounds) {
    const double d = (xy - m.centre).norm();
    if (d < m.radius) z += m.height * (1 + std::cos(M_PI * d / m.radius)) / 2;
  }
  for (const Step& s : terrain_.steps) z += s.height * ramp(s.across(xy), s.width);
  return z;
}

double TerrainSurface::height_at(const Eigen::Vector2d& xy) const {
  double z = relief(xy) - origin_relief_;
  for (const Wave& w : waves_) z += w.amplitude * std::sin(w.k.dot(xy) + w.phase);
  return z;
}

double TerrainSurface::cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double range) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (terrain_.flat()) {
    const double t = direction.z() < -1e-12 ? -origin.z() / direction.z() : kNone;
    return t >= 0 && t <= range ? t : kNone;
  }
  // Sphere tracing: the gap between the ray and the ground closes at most at |dz| + G |dxy|
  // per metre of ray, so a step of gap / that rate never passes through the ground.
  constexpr double kHit = 1e-5;  // m
  const double rate = std::abs(direction.z()) + max_gradient_ * direction.head<2>().norm();
  if (rate <= 0) return kNone;
  double t = 0;
  for (int i = 0; i < 100000 && t <= range; ++i) {
    const Eigen::Vector3d p = origin + t * direction;
    const double gap = p.z() - height_at(p.head<2>());
    if (gap < kHit) return gap < -kHit && t == 0 ? kNone : t;
    t += gap / rate;
  }
  return kNone;
}

std::optional<TerrainProblem> terrain_problem(const Terrain& t) {
  auto outside = [](double v, double low, double high) { return !(v >= low && v <= high); };
  if (!t.slope.allFinite() || t.slope.norm() > 1)
    return TerrainProblem{"slope", "is steeper than 45 degrees: not ground a MAV maps"};
  // Every ray and every box's footprint samples every feature: a bound keeps them cheap.
  constexpr size_t kMaxFeatures = 100;
  if (t.mounds.size() > kMaxFeatures) return TerrainProblem{"mounds", "are more than 100"};
  if (t.steps.size() > kMaxFeatures) return TerrainProblem{"steps", "are more than 100"};
  for (size_t i = 0; i < t.mounds.size(); ++i) {
    const std::string name = "mounds[" + std::to_string(i) + "]";
    if (!t.mounds[i].centre.allFinite() || t.mounds[i].centre.norm() > 1e5)
      return TerrainProblem{name + ".centre", "is not a place on the map"};
    if (outside(t.mounds[i].radius, 0.05, 1000)) return TerrainProblem{name + ".radius", "must be 0.05 to 1000 m"};
    if (outside(t.mounds[i].height, -100, 100)) return TerrainProblem{name + ".height", "must be within 100 m"};
  }
  for (size_t i = 0; i < t.steps.size(); ++i) {
    const std::string name = "steps[" + std::to_string(i) + "]";
    if (!t.steps[i].at.allFinite() || t.steps[i].at.norm() > 1e5)
      return TerrainProblem{name + ".at", "is not a place on the map"};
    if (!std::isfinite(t.steps[i].direction)) return TerrainProblem{name + ".direction", "is not a number"};
    if (outside(t.steps[i].height, -100, 100)) return TerrainProblem{name + ".height", "must be within 100 m"};
    if (outside(t.steps[i].width, 0.001, 100)) return TerrainProblem{name + ".width", "must be 0.001 to 100 m"};
  }
  if (outside(t.roughness, 0, 1)) return TerrainProblem{"roughness", "must be 0 to 1 m RMS"};
  if (outside(t.roughness_wavelength, 0.05, 100))
    return TerrainProblem{"roughness_wavelength", "must be 0.05 to 100 m"};
  return std::nullopt;
}

Terrain terrain_from_config(const Config& section) {
  Terrain terrain;
  if (section.has("slope")) {
    const auto slope = section.numbers("slope", 2);
    terrain.slope = {slope[0], slope[1]};
  }
  for (const Config& m : section.maps("mounds")) {
    const auto centre = m.numbers("centre", 2);
    terrain.mounds.push_back(
        {{centre[0], centre[1]}, m.number("radius", 1, -1e300, 1e300), m.number("height", 0.3, -1e300, 1e300)});
  }
  for (const Config& s : section.maps("steps")) {
    const auto at = s.numbers("at", 2);
    terrain.steps.push_back({{at[0], at[1]},
                             s.number("direction", 0, -360, 360) * M_PI / 180,
                             s.number("height", 0.2, -1e300, 1e300),
                             s.number("width", 0.02, -1e300, 1e300)});
  }
  terrain.roughness = section.number("roughness", 0, -1e300, 1e300);
  terrain.roughness_wavelength = section.number("roughness_wavelength", 0.5, -1e300, 1e300);
  terrain.roughness_seed = static_cast<unsigned>(section.integer("seed", 1, 0, 4294967295LL));
  // The limits live in terrain_problem(), shared with logs and code; named here by key.
  if (const auto problem = terrain_problem(terrain)) section.fail(problem->key, problem->what);
  return terrain;
}

Terrain load_terrain(const std::string& path) {
  const Config file = Config::load(path);
  if (!file.has("terrain")) file.missing("terrain");
  const Terrain terrain = terrain_from_config(file.section("terrain"));
  file.check_all_read();
  return terrain;
}

}  // namespace scanbus::mav_sim
