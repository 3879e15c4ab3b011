#include "scanbus/room_measurement/wall_adjustment.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>

#include "scanbus/units.hpp"

namespace scanbus::room_measurement {

namespace {

constexpr size_t kDeviceTerms = 5;  // range bias, lever arm, pitch offset, yaw error's sine and cosine
constexpr double kHeld = 1e12;      // prior weight that holds an unknown where it is

// One point's equation: a . x = y, touching its wall's offset and turn and the device terms,
// with its weight (its range noise's inverse variance, relative to the noise at 1 m).
struct Row {
  size_t wall, bin;
  long pitch_step;  // the bin's commanded pitch, in bins: the same step in every scan
  double a[2 + kDeviceTerms];
  double y;
  double weight;
};

// The device terms' prior sigmas, in the unknowns' order.
std::array<double, kDeviceTerms> device_sigmas(const AdjustmentSettings& settings) {
  const double yaw = settings.yaw_error_prior_deg * kDegree;
  return {settings.range_bias_prior, settings.lever_arm_prior, settings.pitch_error_prior_deg * kDegree, yaw, yaw};
}

// What the device terms' priors pull towards, in the unknowns' order: a calibration's values.
std::array<double, kDeviceTerms> device_centres(const AdjustmentSettings& settings) {
  return {settings.calibrated_range_bias, settings.calibrated_lever_arm, settings.calibrated_pitch_offset_deg * kDegree,
          0, 0};
}

// Every usable point of the walls as an equation, linearised at the walls' current lines,
// handed to `use` (a million points' rows would not fit the cache). Bins group a servo step's
// rays (the same reported pitch): they share its error; numbered as they first appear.
template <typename Use>
void for_each_row(const std::vector<WallLine>& walls, const AdjustmentSettings& settings, Use use) {
  const double pitch_bin_deg = settings.pitch_bin_deg;
  const double noise_at_1m = settings.range_noise + settings.range_noise_per_metre;
  constexpr size_t kNoBin = ~size_t{0};
  std::vector<size_t> bin_index(static_cast<size_t>(std::ceil(180 / pitch_bin_deg)) + 2, kNoBin);
  size_t bins = 0;
  for (size_t k = 0; k < walls.size(); ++k) {
    const Eigen::Vector2d n = walls[k].normal, along = walls[k].direction();
    for (const auto& point : walls[k].inliers) {
      const Eigen::Vector3d p = point.cast<double>();
      const double range = p.norm(), horizontal = p.head<2>().norm();
      if (range < 1e-6 || horizontal < 1e-6) continue;
      const double sin_pitch = horizontal / range, cos_pitch = p.z() / range;
      const Eigen::Vector2d heading = p.head<2>() / horizontal;  // cos and sin of the yaw
      const double facing = n.dot(heading);
      if (facing * sin_pitch < 0.05) continue;  // grazing: the ray barely meets the wall
      // The regressors at the ray's meeting with the current line, not at the noisy point:
      // range noise in both sides of the equations would bias the turn and the pitch terms.
      const Eigen::Vector3d on_line = walls[k].on_ray(p);
      const double pitch_deg = std::atan2(horizontal, p.z()) / kDegree;
      const long pitch_step = std::lround(pitch_deg / pitch_bin_deg);
      size_t& bin = bin_index[static_cast<size_t>(pitch_step)];
      if (bin == kNoBin) bin = bins++;
      // The line n . q = o through corrected points q = p + b u + L up - range e up, turned by
      // t, and the ray turned about the pole by the once-per-turn yaw error s sin + c cos:
      // o - t (along . p) - b facing sin + L facing cos - e range facing cos
      //   - (s sin + c cos) (n . p across) = n . p.
      const double across = n.dot(Eigen::Vector2d(-on_line.y(), on_line.x()));  // per radian of yaw
      // Weighted by the range noise (three times as large at 5 m as at 1 m), taken at the
      // ray's range to the line: from the noisy range, short returns would weigh more.
      const double noise = settings.range_noise + settings.range_noise_per_metre * on_line.norm();
      use(Row{k,
              bin,
              pitch_step,
              {1.0, -along.dot(on_line.head<2>()), -facing * sin_pitch, facing * cos_pitch,
               -on_line.norm() * facing * cos_pitch, -across * heading.y(), -across * heading.x()},
              n.dot(p.head<2>()),
              noise > 0 ? std::pow(noise_at_1m / noise, 2) : 1.0});  // no noise model: equal weights
    }
  }
}

// Unknown index of a row's coefficient `i`: its wall's offset and turn, then the device terms.
size_t unknown(const Row& row, size_t i, size_t walls) { return i < 2 ? 2 * row.wall + i : 2 * walls + i - 2; }

// One pitch bin's share of the normal equations (the bootstrap resamples whole bins).
struct Block {
  Eigen::MatrixXd normal;  // g x g
  Eigen::VectorXd rhs;     // g
};

void add_row(const Row& row, size_t walls, Block& block) {
  size_t u[2 + kDeviceTerms];
  for (size_t i = 0; i < 2 + kDeviceTerms; ++i) u[i] = unknown(row, i, walls);
  for (size_t i = 0; i < 2 + kDeviceTerms; ++i) {
    const double weighted = row.weight * row.a[i];
    for (size_t j = 0; j < 2 + kDeviceTerms; ++j) block.normal(u[i], u[j]) += weighted * row.a[j];
    block.rhs[u[i]] += weighted * row.y;
  }
}

// A servo step's own pitch error is an unknown of its bin alone, touching its rows as the pitch
// offset does (Row::a's coefficient kPitchOffsetCoefficient, in for_each_row's order: offset,
// turn, range bias, lever arm, pitch offset, yaw sine, yaw cosine): these sums let it be
// eliminated bin by bin (a Schur complement) instead of growing the system by one unknown per step.
constexpr size_t kPitchOffsetCoefficient = 4;

struct StepSums {
  Eigen::VectorXd with_unknowns;   // g: sum of each row's coefficients times its step coefficient
  double squares = 0, with_y = 0;  // sums of the step coefficient squared and times y

  explicit StepSums(Eigen::Index g) : with_unknowns(Eigen::VectorXd::Zero(g)) {}
  void add(const Row& row, size_t walls) {
    const double r = row.a[kPitchOffsetCoefficient], w = row.weight;
    for (size_t i = 0; i < 2 + kDeviceTerms; ++i) with_unknowns[unknown(row, i, walls)] += w * row.a[i] * r;
    squares += w * r * r;
    with_y += w * r * row.y;
  }
  // The step's unknown, with prior weight `prior`, eliminated from its bin's equations.
  void eliminate_from(Block& block, double prior) const {
    const double scale = -1 / (squares + prior);
    block.normal += scale * with_unknowns * with_unknowns.transpose();
    block.rhs += scale * with_y * with_unknowns;
  }
};

struct System {
  std::vector<Block> blocks;      // per pitch bin, each servo step's error eliminated
  std::vector<StepSums> steps;    // per pitch bin; empty without step unknowns
  std::vector<long> pitch_steps;  // per pitch bin: Row::pitch_step
  double step_prior = 0;          // the steps' prior weight; 0: no step unknowns
  Eigen::VectorXd prior;          // g: diagonal prior weights
  Eigen::VectorXd prior_mean;     // g: what they pull towards (an inferred wall's line, the device
                                  // terms' calibrated values; zero otherwise)
  double variance = 0;            // of a weighted row about its wall's line (the priors' scale)
};

System build_system(const std::vector<WallLine>& walls, const AdjustmentSettings& settings) {
  const size_t count = walls.size(), g = 2 * count + kDeviceTerms;
  const Block zero{Eigen::MatrixXd::Zero(g, g), Eigen::VectorXd::Zero(g)};
  System system;
  // Held at zero with the device terms: the steps would take up a common pitch offset.
  const bool step_unknowns = settings.step_error_prior_deg > 0 && settings.estimate_device;
  const StepSums no_step(static_cast<Eigen::Index>(g));
  double squares = 0, rows = 0;
  for_each_row(walls, settings, [&](const Row& row) {
    if (!walls[row.wall].inferred) {
      squares += row.weight * std::pow(row.y - walls[row.wall].offset, 2);
      rows += 1;
    }
    if (row.bin == system.blocks.size()) {
      system.blocks.push_back(zero);
      system.pitch_steps.push_back(row.pitch_step);
      if (step_unknowns) system.steps.push_back(no_step);
    }
    add_row(row, count, system.blocks[row.bin]);
    if (step_unknowns) system.steps[row.bin].add(row, count);
  });
  const double variance = std::max(rows > 0 ? squares / rows : 0.0, 1e-6);
  system.variance = variance;
  if (step_unknowns) {
    const double sigma = settings.step_error_prior_deg * kDegree;
    system.step_prior = variance / (sigma * sigma);
    for (size_t b = 0; b < system.blocks.size(); ++b)
      system.steps[b].eliminate_from(system.blocks[b], system.step_prior);
  }
  system.prior = Eigen::VectorXd::Zero(g);
  system.prior_mean = Eigen::VectorXd::Zero(g);
  for (size_t k = 0; k < count; ++k) {
    if (!walls[k].inferred) continue;  // no points: its line is held where it was placed
    system.prior[2 * k] = variance / std::max(1e-6, walls[k].offset_sigma * walls[k].offset_sigma);
    system.prior_mean[2 * k] = walls[k].offset;
    system.prior[2 * k + 1] = kHeld;
  }
  const auto centres = device_centres(settings);
  for (size_t term = 0; term < kDeviceTerms; ++term) system.prior_mean[2 * count + term] = centres[term];
  if (!settings.estimate_device) {  // held at the calibration's values
    system.prior.tail(kDeviceTerms).setConstant(kHeld);
    return system;
  }
  const auto sigmas = device_sigmas(settings);
  for (size_t term = 0; term < kDeviceTerms; ++term)
    system.prior[2 * count + term] = variance / (sigmas[term] * sigmas[term]);
  return system;
}

// The normal equations of every bin with the priors: the full fit's.
Block all_of(const System& system) {
  Block all{system.prior.asDiagonal(), system.prior.cwiseProduct(system.prior_mean)};
  for (const auto& block : system.blocks) all.normal += block.normal, all.rhs += block.rhs;
  return all;
}

// How far the walls move when device term `term` (in device_sigmas' order) is moved by
// `value` from where it is held: the walls' unknowns re-solved with it held there.
Eigen::VectorXd held_at(const System& system, size_t term, double value) {
  const auto g = system.prior.size();
  const Eigen::MatrixXd normal = all_of(system).normal;
  const Eigen::Index walls = g - static_cast<Eigen::Index>(kDeviceTerms),
                     index = walls + static_cast<Eigen::Index>(term);
  const Eigen::VectorXd shift =
      normal.topLeftCorner(walls, walls).ldlt().solve(-normal.block(0, index, walls, 1) * value);
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

Outline outline(const std::vector<WallLine>& walls, const Eigen::VectorXd& x) {
  Outline o;
  const size_t count = walls.size();
  for (size_t k = 0; k < count; ++k) {
    o.normals.push_back(Eigen::Rotation2Dd(x[2 * k + 1]) * walls[k].normal);
    o.offsets.push_back(x[2 * k]);
  }
  for (size_t i = 0; i < count; ++i) {
    const size_t before = (i + count - 1) % count;
    o.corners.push_back(intersect_lines(o.normals[before], o.offsets[before], o.normals[i], o.offsets[i]));
  }
  for (size_t i = 0; i < count; ++i) o.lengths.push_back((o.corners[(i + 1) % count] - o.corners[i]).norm());
  o.area = polygon_area(o.corners);
  return o;
}

// Variances of the lengths, the corners' positions (summed over x and y) and the area.
struct Spread {
  std::vector<double> lengths, corners;
  double area = 0;

  explicit Spread(size_t count) : lengths(count, 0), corners(count, 0) {}
  void add(const Spread& other) {
    for (size_t i = 0; i < lengths.size(); ++i) lengths[i] += other.lengths[i], corners[i] += other.corners[i];
    area += other.area;
  }
};

// The outlines' variance about their mean, times `scale`.
Spread variance_of(const std::vector<Outline>& outlines, size_t count, double scale) {
  Spread spread(count);
  if (outlines.size() < 2) return spread;
  const double n = static_cast<double>(outlines.size());
  auto variance = [&](auto value) {
    double mean = 0, squares = 0;
    for (const auto& o : outlines) mean += value(o) / n;
    for (const auto& o : outlines) squares += (value(o) - mean) * (value(o) - mean);
    return scale * squares / n;
  };
  for (size_t i = 0; i < count; ++i) {
    spread.lengths[i] = variance([i](const Outline& o) { return o.lengths[i]; });
    spread.corners[i] = variance([i](const Outline& o) { return o.corners[i].x(); }) +
                        variance([i](const Outline& o) { return o.corners[i].y(); });
  }
  spread.area = variance([](const Outline& o) { return o.area; });
  return spread;
}

// Noise, the correlation of a servo step's points and the device terms' estimate (when they are
// estimated): a bootstrap over pitch bins, with a fixed seed (the same cloud gives the same
// sigmas), widened by settings.bootstrap_scale.
Spread bootstrap_spread(const System& system, const std::vector<WallLine>& walls, const AdjustmentSettings& settings) {
  const size_t bins = system.blocks.size();
  std::mt19937 random(1);
  std::uniform_int_distribution<size_t> pick(0, bins - 1);
  std::vector<Outline> outlines;
  for (int b = 0; b < settings.bootstrap; ++b) {
    std::vector<double> weights(bins, 0);
    for (size_t i = 0; i < bins; ++i) weights[pick(random)] += 1;
    outlines.push_back(outline(walls, solve(system, weights)));
  }
  return variance_of(outlines, walls.size(), settings.bootstrap_scale * settings.bootstrap_scale);
}

// What the data cannot pin down, each term moved by its sigma and the walls re-solved: the
// device terms at their priors when they are not estimated (a common range bias moves every
// wall out at once), and an inferred wall's placement (its seen corner's uncertainty).
Spread prior_spread(const System& system, const std::vector<WallLine>& walls, const Eigen::VectorXd& x,
                    const AdjustmentSettings& settings) {
  const size_t count = walls.size();
  const Outline best = outline(walls, x);
  Spread spread(count);
  auto add = [&](const Eigen::VectorXd& shifted_x) {
    const Outline shifted = outline(walls, shifted_x);
    for (size_t i = 0; i < count; ++i) {
      spread.lengths[i] += std::pow(shifted.lengths[i] - best.lengths[i], 2);
      spread.corners[i] += (shifted.corners[i] - best.corners[i]).squaredNorm();
    }
    spread.area += std::pow(shifted.area - best.area, 2);
  };
  const auto sigmas = device_sigmas(settings);
  for (size_t term = 0; term < kDeviceTerms && !settings.estimate_device; ++term)
    add(x + held_at(system, term, sigmas[term]));
  // A calibration's own error: the fit moves with its values as far as their priors weigh.
  const auto centres = device_centres(settings);
  const bool calibrated = std::any_of(centres.begin(), centres.end(), [](double c) { return c != 0; });
  if (settings.estimate_device && calibrated) {
    const auto normal = all_of(system).normal.ldlt();
    for (size_t term = 0; term < 3; ++term) {
      const Eigen::Index index = static_cast<Eigen::Index>(2 * count + term);
      Eigen::VectorXd pull = Eigen::VectorXd::Zero(x.size());
      pull[index] = system.prior[index] * sigmas[term];
      add(x + normal.solve(pull));
    }
  }
  for (size_t k = 0; k < count; ++k) {
    if (!walls[k].inferred) continue;
    Eigen::VectorXd shifted_x = x;
    shifted_x[2 * k] += walls[k].offset_sigma;
    add(shifted_x);
  }
  return spread;
}

// Whether the device terms estimated lie within kPriorSigmas of their priors (the yaw error's
// sine and cosine parts as one amplitude, whatever its phase). Beyond, they took up something
// the model lacks (a wall's points bent by what stands on its line; seen in T-shaped rooms: a
// 6 cm range bias and a 1.4 degree yaw error moved walls by 9 cm).
bool device_within_priors(const Eigen::VectorXd& x, size_t walls, const AdjustmentSettings& settings) {
  constexpr double kPriorSigmas = 3;
  const auto sigmas = device_sigmas(settings);
  const auto centres = device_centres(settings);
  const double* device = x.data() + 2 * walls;
  for (size_t i = 0; i < 3; ++i)
    if (std::abs(device[i] - centres[i]) > kPriorSigmas * sigmas[i]) return false;
  return std::hypot(device[3], device[4]) <= kPriorSigmas * sigmas[3];
}

// The unit's terms (the first three device terms) as the points alone see them: their priors
// taken out, every other unknown eliminated (a Schur complement), scaled by the weighted rows' variance.
void set_unit_information(const System& system, size_t walls, double variance, AdjustedWalls& result) {
  Block all = all_of(system);
  const Eigen::Index g = all.rhs.size(), first = static_cast<Eigen::Index>(2 * walls);
  for (Eigen::Index t = first; t < first + 3; ++t) {
    all.normal(t, t) -= system.prior[t];
    all.rhs[t] -= system.prior[t] * system.prior_mean[t];
  }
  std::vector<Eigen::Index> others;
  for (Eigen::Index i = 0; i < g; ++i)
    if (i < first || i >= first + 3) others.push_back(i);
  const Eigen::MatrixXd n_uo = all.normal(Eigen::seqN(first, 3), others);
  const auto n_oo = all.normal(others, others).ldlt();
  const Eigen::Matrix3d n_uu = all.normal.block(first, first, 3, 3);
  const auto unit_part = [&](const Eigen::VectorXd& rhs) -> Eigen::Vector3d {
    return (rhs.segment(first, 3) - n_uo * n_oo.solve(Eigen::VectorXd(rhs(others)))) / variance;
  };
  result.unit_information = (n_uu - n_uo * n_oo.solve(n_uo.transpose())) / variance;
  result.unit_rhs = unit_part(all.rhs);
  // A step's true error e moves its rows' y by their step coefficient times e; with the step's
  // unknown eliminated under its prior, what stays in the rhs is the coefficients' sums times
  // e prior / (squares + prior). One prior sigma of e, carried to the unit's terms:
  result.unit_step_leaks.clear();
  if (system.step_prior <= 0) return;
  const double step_sigma = std::sqrt(variance / system.step_prior);
  for (size_t b = 0; b < system.steps.size(); ++b) {
    const StepSums& step = system.steps[b];
    const double kept = system.step_prior / (step.squares + system.step_prior);
    result.unit_step_leaks.push_back({system.pitch_steps[b], unit_part(step.with_unknowns * (kept * step_sigma))});
  }
}

void set_device_terms(const Eigen::VectorXd& x, size_t walls, AdjustedWalls& result) {
  result.range_bias = x[2 * walls];
  result.lever_arm = x[2 * walls + 1];
  result.pitch_offset = x[2 * walls + 2];
  result.yaw_error = {x[2 * walls + 3], x[2 * walls + 4]};
}

}  // namespace

AdjustedWalls adjust_walls(const std::vector<WallLine>& walls, const AdjustmentSettings& settings) {
  if (walls.size() < 3) throw std::invalid_argument("adjust_walls needs at least 3 walls");
  const size_t count = walls.size();
  const System system = build_system(walls, settings);
  const size_t bins = system.blocks.size();
  const Eigen::VectorXd x = solve(system, std::vector<double>(bins, 1.0));
  if (settings.estimate_device && !device_within_priors(x, count, settings)) {
    AdjustmentSettings held = settings;  // the walls alone, the device terms' priors in their sigmas
    held.estimate_device = false;
    AdjustedWalls alone = adjust_walls(walls, held);
    alone.device_held = true;
    set_device_terms(x, count, alone);  // reported, not applied: what the device would need
    set_unit_information(system, count, system.variance, alone);
    return alone;
  }
  const Outline best = outline(walls, x);

  AdjustedWalls result;
  result.normals = best.normals;
  result.offsets = best.offsets;
  result.corners = best.corners;
  result.lengths = best.lengths;
  result.area = best.area;
  set_device_terms(x, count, result);
  if (settings.estimate_device) set_unit_information(system, count, system.variance, result);
  result.length_sigmas.assign(count, 0);
  result.corner_sigmas.assign(count, 0);
  if (settings.bootstrap <= 0 || bins < 2) return result;

  Spread spread = bootstrap_spread(system, walls, settings);
  spread.add(prior_spread(system, walls, x, settings));
  for (size_t i = 0; i < count; ++i) {
    result.length_sigmas[i] = std::sqrt(spread.lengths[i]);
    result.corner_sigmas[i] = std::sqrt(spread.corners[i]);
  }
  result.area_sigma = std::sqrt(spread.area);
  return result;
}

}  // namespace scanbus::room_measurement
