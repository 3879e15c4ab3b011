#include "scanbus/room_measurement/wall_adjustment.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

namespace scanbus::room_measurement {

namespace {

constexpr double kDegree = M_PI / 180;

// One pitch bin's share of the normal equations (the bootstrap resamples whole bins).
// Unknowns: per wall an offset and a turn, then the range bias, the lever arm and the pitch
// offset. Each point's row touches five of them.
struct Block {
  Eigen::MatrixXd normal;  // g x g
  Eigen::VectorXd rhs;     // g
};

struct System {
  std::vector<Block> blocks;
  Eigen::VectorXd prior;       // g: diagonal prior weights
  Eigen::VectorXd prior_mean;  // g: what they pull towards (an inferred wall's line; zero otherwise)
};

System build_system(const std::vector<WallLine>& walls, const AdjustmentSettings& settings, double variance) {
  System system;
  const size_t g = 2 * walls.size() + 3, bias = g - 3, lever = g - 2, pitch = g - 1;
  std::map<long, size_t> bin_index;
  for (size_t k = 0; k < walls.size(); ++k) {
    const Eigen::Vector2d n = walls[k].normal, along = walls[k].direction();
    for (const auto& point : walls[k].inliers) {
      const Eigen::Vector3d p = point.cast<double>();
      const double range = p.norm(), horizontal = p.head<2>().norm();
      if (range < 1e-6 || horizontal < 1e-6) continue;
      const double sin_pitch = horizontal / range, cos_pitch = p.z() / range;
      const double facing = n.dot(p.head<2>() / horizontal);
      if (facing * sin_pitch < 0.05) continue;  // grazing: the ray barely meets the wall
      // The regressors at the ray's meeting with the current line, not at the noisy point:
      // range noise in both sides of the equations would bias the turn and the pitch terms.
      const Eigen::Vector3d on_line = p * (walls[k].offset / (facing * sin_pitch * range));
      const long bin = static_cast<long>(std::floor(std::acos(std::clamp(cos_pitch, -1.0, 1.0)) / kDegree / settings.pitch_bin_deg));
      auto [it, added] = bin_index.try_emplace(bin, system.blocks.size());
      if (added) system.blocks.push_back({Eigen::MatrixXd::Zero(g, g), Eigen::VectorXd::Zero(g)});
      Block& block = system.blocks[it->second];
      // The line n . q = o through corrected points q = p + b u + L up - range e up, turned by t:
      // o - t (along . p) - b facing sin + L facing cos - e range facing cos = n . p.
      const size_t index[5] = {2 * k, 2 * k + 1, bias, lever, pitch};
      const double a[5] = {1.0, -along.dot(on_line.head<2>()), -facing * sin_pitch, facing * cos_pitch,
                           -on_line.norm() * facing * cos_pitch};
      const double y = n.dot(p.head<2>());
      for (int i = 0; i < 5; ++i) {
        for (int j = 0; j < 5; ++j) block.normal(index[i], index[j]) += a[i] * a[j];
        block.rhs[index[i]] += a[i] * y;
      }
    }
  }
  system.prior = Eigen::VectorXd::Zero(g);
  system.prior_mean = Eigen::VectorXd::Zero(g);
  for (size_t k = 0; k < walls.size(); ++k) {
    if (!walls[k].inferred) continue;  // no points: its line is held where it was placed
    system.prior[2 * k] = variance / std::max(1e-6, walls[k].offset_sigma * walls[k].offset_sigma);
    system.prior_mean[2 * k] = walls[k].offset;
    system.prior[2 * k + 1] = 1e12;
  }
  if (!settings.estimate_device) {  // held at zero
    system.prior.tail(3).setConstant(1e12);
    return system;
  }
  system.prior[bias] = variance / (settings.range_bias_prior * settings.range_bias_prior);
  system.prior[lever] = variance / (settings.lever_arm_prior * settings.lever_arm_prior);
  const double pitch_prior = settings.pitch_error_prior_deg * kDegree;
  system.prior[pitch] = variance / (pitch_prior * pitch_prior);
  return system;
}

// How far the walls move when device term `term` (0 range bias, 1 lever arm, 2 pitch offset)
// is `value` instead of zero: the walls' unknowns re-solved with it held there.
Eigen::VectorXd held_at(const System& system, size_t term, double value) {
  const auto g = system.prior.size();
  Eigen::MatrixXd normal = system.prior.asDiagonal();
  for (const auto& block : system.blocks) normal += block.normal;
  const Eigen::Index walls = g - 3, index = walls + static_cast<Eigen::Index>(term);
  const Eigen::VectorXd shift = normal.topLeftCorner(walls, walls).ldlt().solve(-normal.block(0, index, walls, 1) * value);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(g);
  x.head(walls) = shift;
  return x;
}

// The unknowns for blocks weighted by `weights` (a bootstrap's counts).
Eigen::VectorXd solve(const System& system, const std::vector<double>& weights) {
  Eigen::MatrixXd normal = system.prior.asDiagonal();
  Eigen::VectorXd rhs = system.prior.cwiseProduct(system.prior_mean);
  for (size_t j = 0; j < system.blocks.size(); ++j) {
    if (weights[j] == 0) continue;
    normal += weights[j] * system.blocks[j].normal;
    rhs += weights[j] * system.blocks[j].rhs;
  }
  return normal.ldlt().solve(rhs);
}

struct Outline {
  std::vector<Eigen::Vector2d> normals, corners;
  std::vector<double> offsets, lengths;
  double area = 0;
};

Outline outline(const std::vector<WallLine>& walls, const Eigen::VectorXd& x, const std::vector<double>& shift = {}) {
  Outline o;
  const size_t count = walls.size();
  for (size_t k = 0; k < count; ++k) {
    o.normals.push_back(Eigen::Rotation2Dd(x[2 * k + 1]) * walls[k].normal);
    o.offsets.push_back(x[2 * k] + (shift.empty() ? 0.0 : shift[k]));
  }
  for (size_t i = 0; i < count; ++i) {
    const size_t before = (i + count - 1) % count;
    o.corners.push_back(intersect_lines(o.normals[before], o.offsets[before], o.normals[i], o.offsets[i]));
  }
  for (size_t i = 0; i < count; ++i) o.lengths.push_back((o.corners[(i + 1) % count] - o.corners[i]).norm());
  o.area = polygon_area(o.corners);
  return o;
}

}  // namespace

AdjustedWalls adjust_walls(const std::vector<WallLine>& walls, const AdjustmentSettings& settings) {
  if (walls.size() < 3) throw std::invalid_argument("adjust_walls needs at least 3 walls");
  double variance = 0;  // of the seen walls' points
  size_t seen = 0;
  for (const auto& wall : walls) variance += wall.inferred ? 0 : wall.rms * wall.rms, seen += !wall.inferred;
  variance /= static_cast<double>(std::max<size_t>(1, seen));
  const System system = build_system(walls, settings, std::max(variance, 1e-6));
  const size_t bins = system.blocks.size(), count = walls.size();
  const Eigen::VectorXd x = solve(system, std::vector<double>(bins, 1.0));
  const Outline best = outline(walls, x);

  AdjustedWalls result;
  result.normals = best.normals;
  result.offsets = best.offsets;
  result.corners = best.corners;
  result.lengths = best.lengths;
  result.area = best.area;
  result.range_bias = x[2 * count];
  result.lever_arm = x[2 * count + 1];
  result.pitch_offset = x[2 * count + 2];
  result.length_sigmas.assign(count, 0);

  if (settings.bootstrap <= 0 || bins < 2) return result;

  // Bootstrap over pitch bins, with a fixed seed: the same cloud gives the same sigmas.
  std::mt19937 random(1);
  std::uniform_int_distribution<size_t> pick(0, bins - 1);
  std::vector<double> sum(count, 0), sum_squares(count, 0);
  double area_sum = 0, area_squares = 0;
  for (int b = 0; b < settings.bootstrap; ++b) {
    std::vector<double> weights(bins, 0);
    for (size_t i = 0; i < bins; ++i) weights[pick(random)] += 1;
    const Outline replicate = outline(walls, solve(system, weights));
    for (size_t i = 0; i < count; ++i) {
      const double d = replicate.lengths[i] - best.lengths[i];
      sum[i] += d, sum_squares[i] += d * d;
    }
    const double d = replicate.area - best.area;
    area_sum += d, area_squares += d * d;
  }
  const double n = settings.bootstrap;
  // The device's errors the data cannot pin down: each term at its prior sigma, the walls
  // re-solved (a common range bias moves every wall out at once).
  std::vector<double> model_lengths(count, 0);
  double model_area = 0;
  const double device_sigmas[3] = {settings.range_bias_prior, settings.lever_arm_prior, settings.pitch_error_prior_deg * kDegree};
  auto add_model_term = [&](const Eigen::VectorXd& shifted_x) {
    const Outline shifted = outline(walls, shifted_x);
    for (size_t i = 0; i < count; ++i) model_lengths[i] += std::pow(shifted.lengths[i] - best.lengths[i], 2);
    model_area += std::pow(shifted.area - best.area, 2);
  };
  for (size_t term = 0; term < 3 && !settings.estimate_device; ++term)
    add_model_term(x + held_at(system, term, device_sigmas[term]));
  for (size_t k = 0; k < count; ++k) {  // where an inferred wall was placed: its seen corner's uncertainty
    if (!walls[k].inferred) continue;
    Eigen::VectorXd shifted_x = x;
    shifted_x[2 * k] += walls[k].offset_sigma;
    add_model_term(shifted_x);
  }
  for (size_t i = 0; i < count; ++i) {
    const double mean = sum[i] / n;
    result.length_sigmas[i] = std::sqrt(std::max(0.0, sum_squares[i] / n - mean * mean) + model_lengths[i]);
  }
  const double area_mean = area_sum / n;
  result.area_sigma = std::sqrt(std::max(0.0, area_squares / n - area_mean * area_mean) + model_area);
  return result;
}

}  // namespace scanbus::room_measurement
