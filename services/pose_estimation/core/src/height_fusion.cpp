#include "scanbus/pose_estimation/height_fusion.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <set>

namespace scanbus::pose_estimation {

namespace {

// A linear residual as a Ceres cost: one parameter block of size 1 per state.
class LinearCost : public ceres::CostFunction {
 public:
  LinearCost(std::vector<double> coefficients, double value, double sigma)
      : coefficients_(std::move(coefficients)), value_(value), sigma_(sigma) {
    set_num_residuals(1);
    for (size_t i = 0; i < coefficients_.size(); ++i) mutable_parameter_block_sizes()->push_back(1);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    double sum = -value_;
    for (size_t i = 0; i < coefficients_.size(); ++i) sum += coefficients_[i] * parameters[i][0];
    residuals[0] = sum / sigma_;
    if (jacobians)
      for (size_t i = 0; i < coefficients_.size(); ++i)
        if (jacobians[i]) jacobians[i][0] = coefficients_[i] / sigma_;
    return true;
  }

 private:
  std::vector<double> coefficients_;
  double value_, sigma_;
};

// Index of the last of sorted (stamp, state) pairs at or before t (0 when t precedes all).
size_t before(const std::deque<std::pair<double, long>>& entries, double t) {
  const auto later = std::upper_bound(entries.begin(), entries.end(), t,
                                      [](double value, const auto& entry) { return value < entry.first; });
  return later == entries.begin() ? 0 : static_cast<size_t>(later - entries.begin()) - 1;
}

}  // namespace

HeightFusion::HeightFusion(FusionSettings settings) : settings_(settings) {}
HeightFusion::~HeightFusion() = default;

long HeightFusion::new_state(double initial) {
  states_[next_state_] = initial;
  return next_state_++;
}

void HeightFusion::add_barometer(double stamp, double altitude) {
  if (!first_altitude_) first_altitude_ = altitude;
  pending_.push_back({stamp, altitude, settings_.baro_sigma});
}

double HeightFusion::add_node(double stamp, std::optional<double> change, std::optional<double> clearance) {
  if (change && last_change_ && stamp - last_change_->first <= settings_.gate_memory &&
      std::abs(*change - last_change_->second) > settings_.change_gate) {
    ++changes_rejected_;
    change.reset();
  }
  if (change) last_change_ = {stamp, *change};
  const bool first = nodes_.empty();
  const double predicted = first ? first_altitude_.value_or(0) : states_.at(nodes_.back().second) + change.value_or(0);
  const long height = new_state(predicted);
  if (!first && change) {
    residuals_.push_back({{nodes_.back().second, height}, {-1, 1}, *change, settings_.change_sigma,
                          settings_.change_loss / settings_.change_sigma});
  } else if (!first) {
    // No change measured (a failed match, a blind laser): the height wanders as a random
    // walk between the nodes (whatever their rate), so it does not follow each barometer
    // sample's noise.
    const double dt = stamp - nodes_.back().first;
    residuals_.push_back({{nodes_.back().second, height}, {-1, 1}, 0.0, std::max(settings_.height_walk * std::sqrt(dt), 1e-3)});
  }
  nodes_.emplace_back(stamp, height);
  if (clearance) add_clearance(stamp, height, *clearance);
  while (biases_.empty() || biases_.back().first < stamp) {
    const double at = biases_.empty() ? stamp : biases_.back().first + settings_.bias_spacing;
    const long bias = new_state(biases_.empty() ? 0.0 : states_.at(biases_.back().second));
    if (biases_.empty()) {
      residuals_.push_back({{bias}, {1}, 0.0, settings_.initial_bias_sigma});
    } else {
      const double sigma = settings_.bias_random_walk * std::sqrt(settings_.bias_spacing);
      residuals_.push_back({{biases_.back().second, bias}, {-1, 1}, 0.0, sigma});
    }
    biases_.emplace_back(at, bias);
  }
  // Samples up to this node now have nodes on both sides (or at the first node).
  auto ready = std::stable_partition(pending_.begin(), pending_.end(), [&](const Sample& s) { return s.stamp <= stamp; });
  for (auto it = pending_.begin(); it != ready; ++it) add_sample_residual(*it);
  pending_.erase(pending_.begin(), ready);
  slide();
  if (++since_solve_ >= settings_.solve_every) {
    solve();
    since_solve_ = 0;
  }
  return states_.at(nodes_.back().second);
}

// height - level = clearance, the level the known one nearest to where the prediction puts
// the ground (a new one when none is within the gate).
void HeightFusion::add_clearance(double stamp, long height, double clearance) {
  const double ground = states_.at(height) - clearance;
  auto nearest = std::min_element(levels_.begin(), levels_.end(), [&](const Level& a, const Level& b) {
    return std::abs(states_.at(a.state) - ground) < std::abs(states_.at(b.state) - ground);
  });
  if (nearest == levels_.end() || std::abs(states_.at(nearest->state) - ground) > settings_.level_gate) {
    if (static_cast<int>(levels_.size()) >= settings_.max_levels) {
      const auto oldest = std::min_element(levels_.begin(), levels_.end(),
                                           [](const Level& a, const Level& b) { return a.seen < b.seen; });
      const long state = oldest->state;
      levels_.erase(oldest);
      marginalise({state});
    }
    levels_.push_back({new_state(ground), stamp});
    nearest = std::prev(levels_.end());
  }
  nearest->seen = stamp;
  residuals_.push_back({{height, nearest->state}, {1, -1}, clearance, settings_.clearance_sigma,
                        settings_.clearance_loss / settings_.clearance_sigma});
}

// Height and bias interpolated linearly between their states at the sample's time.
void HeightFusion::add_sample_residual(const Sample& sample) {
  Linear residual{{}, {}, sample.value, sample.sigma};
  auto interpolate = [&](const std::deque<std::pair<double, long>>& entries) {
    const size_t i = before(entries, sample.stamp), j = std::min(i + 1, entries.size() - 1);
    const double span = entries[j].first - entries[i].first;
    const double weight = span > 0 ? std::clamp((sample.stamp - entries[i].first) / span, 0.0, 1.0) : 0.0;
    residual.states.push_back(entries[i].second);
    residual.coefficients.push_back(i == j ? 1.0 : 1 - weight);
    if (i != j) {
      residual.states.push_back(entries[j].second);
      residual.coefficients.push_back(weight);
    }
  };
  interpolate(nodes_);
  interpolate(biases_);
  double estimate = 0;
  for (size_t i = 0; i < residual.states.size(); ++i) estimate += residual.coefficients[i] * states_.at(residual.states[i]);
  // 5 sigma of the sample and of the estimate: a height uncertain for want of changes (a
  // blind laser) widens the gate rather than shutting the barometer out.
  if (std::abs(sample.value - estimate) <= 5 * std::hypot(sample.sigma, height_sigma_)) {
    barometer_off_since_.reset();
  } else {
    ++barometer_outliers_;
    if (!barometer_off_since_) barometer_off_since_ = sample.stamp;
    if (sample.stamp - *barometer_off_since_ < settings_.baro_gate_time) return;
  }
  residuals_.push_back(std::move(residual));
}

void HeightFusion::slide() {
  const double cutoff = nodes_.back().first - settings_.window;
  std::vector<long> dropped;
  while (nodes_.size() > 2 && nodes_[1].first <= cutoff) {
    dropped.push_back(nodes_.front().second);
    nodes_.pop_front();
  }
  while (biases_.size() > 2 && biases_[1].first <= nodes_.front().first) {
    dropped.push_back(biases_.front().second);
    biases_.pop_front();
  }
  if (!dropped.empty()) marginalise(dropped);
}

void HeightFusion::normal_equations(const std::vector<Linear>& residuals, const std::vector<long>& order,
                                    Eigen::MatrixXd& H, Eigen::VectorXd& g) const {
  const long n = static_cast<long>(order.size());
  std::map<long, long> index;
  for (long i = 0; i < n; ++i) index[order[i]] = i;
  H = Eigen::MatrixXd::Zero(n, n);
  g = Eigen::VectorXd::Zero(n);
  for (const auto& residual : residuals) {
    // A residual touches a few states: accumulate only their entries.
    const size_t m = residual.states.size();
    std::vector<long> at(m);
    double r = -residual.value;
    for (size_t i = 0; i < m; ++i) {
      at[i] = index.at(residual.states[i]);
      r += residual.coefficients[i] * states_.at(residual.states[i]);
    }
    r /= residual.sigma;
    double weight = 1.0;  // the loss's derivative at r^2, as Ceres weighs the residual
    if (residual.cauchy > 0) weight = 1 / (1 + r * r / (residual.cauchy * residual.cauchy));
    for (size_t i = 0; i < m; ++i) {
      const double ji = residual.coefficients[i] / residual.sigma;
      g[at[i]] += weight * ji * r;
      for (size_t j = 0; j < m; ++j) H(at[i], at[j]) += weight * ji * residual.coefficients[j] / residual.sigma;
    }
  }
}

// The residuals touching the dropped states, linearised at the current estimate, become
// one Gaussian prior on the states they share with the rest: H_kk - H_kd H_dd^-1 H_dk, the
// Schur complement. The previous prior joins them, so there is only ever one (its rows on
// long-lived states, the ground levels, would otherwise pile up).
void HeightFusion::marginalise(const std::vector<long>& dropped) {
  const std::set<long> gone(dropped.begin(), dropped.end());
  std::vector<Linear> touching, kept;
  for (auto& residual : residuals_) {
    const bool touches = residual.prior || std::any_of(residual.states.begin(), residual.states.end(),
                                                       [&](long s) { return gone.count(s); });
    (touches ? touching : kept).push_back(std::move(residual));
  }
  std::vector<long> order(dropped);  // dropped first, then the boundary
  for (const auto& residual : touching)
    for (long s : residual.states)
      if (std::find(order.begin(), order.end(), s) == order.end()) order.push_back(s);
  const long n = static_cast<long>(order.size()), d = static_cast<long>(dropped.size()), k = n - d;
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  normal_equations(touching, order, H, g);
  residuals_ = std::move(kept);
  for (long s : dropped) states_.erase(s);
  if (k == 0) return;
  const Eigen::MatrixXd Hdd = H.topLeftCorner(d, d) + 1e-9 * Eigen::MatrixXd::Identity(d, d);
  const Eigen::LDLT<Eigen::MatrixXd> solver(Hdd);
  const Eigen::MatrixXd Hkd = H.bottomLeftCorner(k, d);
  const Eigen::MatrixXd prior = H.bottomRightCorner(k, k) - Hkd * solver.solve(Hkd.transpose());
  const Eigen::VectorXd gradient = g.tail(k) - Hkd * solver.solve(g.head(d));
  // 1/2 |L^T (x - x0) + L^-1 g|^2 with L L^T = prior: as k linear residuals of sigma 1.
  const Eigen::LLT<Eigen::MatrixXd> cholesky(prior + 1e-9 * Eigen::MatrixXd::Identity(k, k));
  const Eigen::MatrixXd Lt = cholesky.matrixU();
  const Eigen::VectorXd offset = cholesky.matrixL().solve(gradient);
  Eigen::VectorXd x0(k);
  for (long i = 0; i < k; ++i) x0[i] = states_.at(order[d + i]);
  const Eigen::VectorXd value = Lt * x0 - offset;
  for (long i = 0; i < k; ++i) {
    Linear row{{}, {}, value[i], 1.0, 0.0, true};
    for (long j = i; j < k; ++j) {
      if (Lt(i, j) == 0) continue;
      row.states.push_back(order[d + j]);
      row.coefficients.push_back(Lt(i, j));
    }
    if (!row.states.empty()) residuals_.push_back(std::move(row));
  }
}

void HeightFusion::solve() {
  ceres::Problem::Options problem_options;
  ceres::Problem problem(problem_options);
  for (const auto& residual : residuals_) {
    std::vector<double*> blocks;
    for (long s : residual.states) blocks.push_back(&states_.at(s));
    ceres::LossFunction* loss = residual.cauchy > 0 ? new ceres::CauchyLoss(residual.cauchy) : nullptr;
    problem.AddResidualBlock(new LinearCost(residual.coefficients, residual.value, residual.sigma), loss, blocks);
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 10;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  // The newest height's marginal standard deviation: the last diagonal entry of H^-1.
  std::vector<long> order;
  for (const auto& [state, value] : states_) order.push_back(state);
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  normal_equations(residuals_, order, H, g);
  const long newest = std::find(order.begin(), order.end(), nodes_.back().second) - order.begin();
  const Eigen::VectorXd unit = Eigen::VectorXd::Unit(static_cast<long>(order.size()), newest);
  height_sigma_ = std::sqrt(std::max(0.0, H.ldlt().solve(unit)[newest]));
}

double HeightFusion::height() const {
  return nodes_.empty() ? first_altitude_.value_or(0) : states_.at(nodes_.back().second);
}
double HeightFusion::bias() const { return biases_.empty() ? 0 : states_.at(biases_.back().second); }
size_t HeightFusion::nodes_in_window() const { return nodes_.size(); }

}  // namespace scanbus::pose_estimation
