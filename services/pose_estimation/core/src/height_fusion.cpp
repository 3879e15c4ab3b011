#include "scanbus/pose_estimation/height_fusion.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace scanbus::pose_estimation {

namespace {

// Index of the last of sorted (stamp, state) pairs at or before t (0 when t precedes all).
size_t before(const std::deque<std::pair<double, long>>& entries, double t) {
  const auto later = std::upper_bound(entries.begin(), entries.end(), t,
                                      [](double value, const auto& entry) { return value < entry.first; });
  return later == entries.begin() ? 0 : static_cast<size_t>(later - entries.begin()) - 1;
}

}  // namespace

// Marginalising factorises the prior: done twice a second for the states older than the
// window rather than at every scan.
constexpr double kSlideEvery = 0.5;  // s

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

void HeightFusion::add_gps(double stamp, double altitude, double vertical_sigma) {
  if (!(vertical_sigma > 0) || !std::isfinite(vertical_sigma) || !std::isfinite(altitude)) return;
  gps_sigma_ = vertical_sigma;
  pending_gps_.push_back({stamp, altitude, vertical_sigma});
}

double HeightFusion::add_node(double stamp, std::optional<double> change, const std::vector<GroundReturn>& ground) {
  if (change && last_change_ && stamp - last_change_->first <= settings_.gate_memory &&
      std::abs(*change - last_change_->second) > settings_.change_gate) {
    ++changes_rejected_;
    change.reset();
  }
  if (change) last_change_ = {stamp, *change};
  const bool first = nodes_.empty();
  const double predicted = first ? first_altitude_.value_or(0) : states_.at(nodes_.back().second) + change.value_or(0);
  // The first node's gates, before its solve, see one barometer altitude: that sample's sigma.
  if (first) height_sigma_ = std::hypot(settings_.baro_sigma, settings_.initial_bias_sigma);
  const long height = new_state(predicted);
  const bool saw_ground = add_ground(stamp, height, ground);
  if (!first && change && !(saw_ground && previous_saw_ground_)) {
    // Over ground seen by both scans the change is that of the depth, which the cells
    // measure already: only without ground is it the height's.
    residuals_.push_back({{nodes_.back().second, height},
                          {-1, 1},
                          *change,
                          settings_.change_sigma,
                          settings_.change_loss / settings_.change_sigma});
  } else if (!first && !change) {
    // No change measured (a failed match, a blind laser): the height wanders as a random
    // walk between the nodes (whatever their rate), so it does not follow each barometer
    // sample's noise.
    const double dt = stamp - nodes_.back().first;
    residuals_.push_back(
        {{nodes_.back().second, height}, {-1, 1}, 0.0, std::max(settings_.height_walk * std::sqrt(dt), 1e-3)});
  }
  previous_saw_ground_ = saw_ground;
  nodes_.emplace_back(stamp, height);
  extend(biases_, stamp, settings_.initial_bias_sigma, settings_.bias_random_walk * std::sqrt(settings_.bias_spacing));
  if (gps_sigma_) {
    // A first-order Gauss-Markov wander of the fix's sigma: each state decays towards zero, so
    // the fixes over the whole flight, not the first ones, set the absolute height (a random
    // walk, as this was, kept the first fixes' error for the flight: 5 cm over a slope).
    const double decay = std::exp(-settings_.bias_spacing / settings_.gps_wander_time);
    extend(gps_biases_, stamp, *gps_sigma_, *gps_sigma_ * std::sqrt(1 - decay * decay), decay);
  }
  // Samples up to this node now have nodes on both sides (or at the first node).
  const auto up_to_node = [&](const Sample& sample) { return sample.stamp <= stamp; };
  const bool tied_first = first && (std::any_of(pending_.begin(), pending_.end(), up_to_node) ||
                                    std::any_of(pending_gps_.begin(), pending_gps_.end(), up_to_node));
  auto ready = std::stable_partition(pending_.begin(), pending_.end(), up_to_node);
  for (auto it = pending_.begin(); it != ready; ++it) add_barometer_residual(*it);
  pending_.erase(pending_.begin(), ready);
  ready = std::stable_partition(pending_gps_.begin(), pending_gps_.end(), up_to_node);
  for (auto it = pending_gps_.begin(); it != ready; ++it) residuals_.push_back(interpolated(*it, gps_biases_));
  pending_gps_.erase(pending_gps_.begin(), ready);
  slide();
  // The first node is solved at once when an altitude ties it: unsolved, its height (and
  // those propagated from it until the next solve) would be one barometer sample, 0.3 m off,
  // where a fix says 2 cm; solved without any altitude, its sigma would be unbounded.
  if (++since_solve_ >= settings_.solve_every || tied_first) {
    solve();
    since_solve_ = 0;
  }
  return states_.at(nodes_.back().second);
}

// A bias with states bias_spacing apart, reaching past `stamp`: each state is `decay` times
// the one before plus a step (1: a random walk; below 1: a first-order Gauss-Markov process).
void HeightFusion::extend(Chain& biases, double stamp, double initial_sigma, double step_sigma, double decay) {
  while (biases.empty() || biases.back().first < stamp) {
    const double at = biases.empty() ? stamp : biases.back().first + settings_.bias_spacing;
    const long bias = new_state(biases.empty() ? 0.0 : decay * states_.at(biases.back().second));
    if (biases.empty()) {
      residuals_.push_back({{bias}, {1}, 0.0, initial_sigma});
    } else {
      residuals_.push_back({{biases.back().second, bias}, {-decay, 1}, 0.0, step_sigma});
    }
    biases.emplace_back(at, bias);
  }
}

// In each cell the median return of the scan (a box or a stone in the cell is outvoted):
// height - ground(xy) = depth, the ground interpolated between the cell's corners. True when
// a cell entered.
bool HeightFusion::add_ground(double stamp, long height, const std::vector<GroundReturn>& ground) {
  const double size = settings_.cell_size;
  std::map<Cell, std::vector<GroundReturn>> cells;
  for (const auto& ret : ground) {
    constexpr double kFarthest = 1e9;  // m: beyond, a cell index would not fit (a fix gone wild)
    if (!(ret.xy.cwiseAbs().maxCoeff() < kFarthest) || !std::isfinite(ret.depth)) continue;
    cells[{static_cast<long>(std::floor(ret.xy.x() / size)), static_cast<long>(std::floor(ret.xy.y() / size))}]
        .push_back(ret);
  }
  bool entered = false;
  for (auto& [cell, returns] : cells) {
    if (static_cast<int>(returns.size()) < settings_.min_cell_returns) continue;
    const auto median = median_return(std::move(returns));
    const double fx = median->xy.x() / size - static_cast<double>(cell.first);
    const double fy = median->xy.y() / size - static_cast<double>(cell.second);
    Linear residual{{height},
                    {1.0},
                    median->depth,
                    settings_.clearance_sigma,
                    settings_.clearance_loss / settings_.clearance_sigma};
    const double initial = states_.at(height) - median->depth;
    bool known = true;
    double predicted = states_.at(height), lowest = INFINITY, highest = -INFINITY;
    for (const auto& [dx, dy, weight] : {std::tuple{0L, 0L, (1 - fx) * (1 - fy)}, std::tuple{1L, 0L, fx * (1 - fy)},
                                         std::tuple{0L, 1L, (1 - fx) * fy}, std::tuple{1L, 1L, fx * fy}}) {
      const Cell at{cell.first + dx, cell.second + dy};
      known = known && (corners_.count(at) || known_ground_.count(at));
      const long state = corner(at, stamp, initial);
      residual.states.push_back(state);
      residual.coefficients.push_back(-weight);
      predicted -= weight * states_.at(state);
      lowest = std::min(lowest, states_.at(state));
      highest = std::max(highest, states_.at(state));
    }
    // Corners apart by more than the gate have a step or an edge between them: the ramp
    // they interpolate is not there.
    const double gate = std::max(settings_.clearance_gate, 5 * height_sigma_);
    if (known && (std::abs(predicted - median->depth) > gate || highest - lowest > gate)) {
      ++cells_gated_;
      continue;
    }
    residuals_.push_back(std::move(residual));
    entered = true;
  }
  return entered;
}

// The corner's state, made when it is not in the problem: from its known height when it
// was marginalised, from the map origin's altitude at the origin, else from the scan.
long HeightFusion::corner(const Cell& cell, double stamp, double initial) {
  if (auto it = corners_.find(cell); it != corners_.end()) {
    it->second.seen = stamp;
    return it->second.state;
  }
  const auto known = known_ground_.find(cell);
  const long state = new_state(known != known_ground_.end() ? known->second.height : initial);
  if (known != known_ground_.end()) {
    residuals_.push_back({{state}, {1}, known->second.height, known->second.sigma});
  } else if (settings_.origin_on_ground && cell == Cell{0, 0}) {
    residuals_.push_back({{state}, {1}, 0.0, settings_.origin_sigma});
  }
  const double gradient = settings_.ground_gradient_sigma * settings_.cell_size;
  for (const Cell& next : {Cell{cell.first - 1, cell.second}, Cell{cell.first + 1, cell.second},
                           Cell{cell.first, cell.second - 1}, Cell{cell.first, cell.second + 1}}) {
    if (auto it = corners_.find(next); it != corners_.end())
      residuals_.push_back({{it->second.state, state}, {-1, 1}, 0.0, gradient});
  }
  corners_[cell] = {state, stamp};
  return state;
}

// Height and bias interpolated linearly between their states at the sample's time.
HeightFusion::Linear HeightFusion::interpolated(const Sample& sample, const Chain& biases) const {
  Linear residual{{}, {}, sample.value, sample.sigma};
  auto interpolate = [&](const Chain& entries) {
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
  interpolate(biases);
  return residual;
}

void HeightFusion::add_barometer_residual(const Sample& sample) {
  Linear residual = interpolated(sample, biases_);
  double estimate = 0;
  for (size_t i = 0; i < residual.states.size(); ++i)
    estimate += residual.coefficients[i] * states_.at(residual.states[i]);
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
  if (nodes_.size() <= 2 || nodes_[1].first > cutoff - kSlideEvery) return;
  std::vector<std::pair<double, long>> settling;  // the nodes leaving
  while (nodes_.size() > 2 && nodes_[1].first <= cutoff) {
    settling.push_back(nodes_.front());
    nodes_.pop_front();
  }
  std::vector<long> dropped;
  for (Chain* biases : {&biases_, &gps_biases_}) {
    while (biases->size() > 2 && (*biases)[1].first <= nodes_.front().first) {
      dropped.push_back(biases->front().second);
      biases->pop_front();
    }
  }
  // Beyond max_corners the least recently seen leave, with their height and its standard
  // deviation, down to nine tenths of the bound (one factorisation for many).
  std::vector<std::map<Cell, Corner>::iterator> leaving;
  if (static_cast<int>(corners_.size()) > settings_.max_corners) {
    for (auto it = corners_.begin(); it != corners_.end(); ++it)
      if (it->second.seen < nodes_.front().first) leaving.push_back(it);
    std::sort(leaving.begin(), leaving.end(),
              [](const auto& a, const auto& b) { return a->second.seen < b->second.seen; });
    leaving.resize(std::min(leaving.size(), corners_.size() - static_cast<size_t>(settings_.max_corners * 9 / 10)));
  }
  std::vector<long> asked;
  for (const auto& [stamp, state] : settling) asked.push_back(state);
  for (const auto& it : leaving) asked.push_back(it->second.state);
  const std::vector<double> sigmas = marginal_sigmas(asked);
  for (size_t i = 0; i < settling.size(); ++i) {
    settle(settling[i].first, settling[i].second, sigmas[i]);
    dropped.push_back(settling[i].second);
  }
  for (size_t i = 0; i < leaving.size(); ++i) {
    const long state = leaving[i]->second.state;
    known_ground_[leaving[i]->first] = {states_.at(state), sigmas[settling.size() + i]};
    dropped.push_back(state);
    corners_.erase(leaving[i]);
  }
  if (!dropped.empty()) marginalise(dropped);
}

std::vector<double> HeightFusion::marginal_sigmas(const std::vector<long>& states) const {
  if (states.empty()) return {};
  std::vector<long> order;
  for (const auto& [state, value] : states_) order.push_back(state);
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd g;
  normal_equations(residuals_, order, H, g);
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(H);
  if (solver.info() != Eigen::Success) return std::vector<double>(states.size(), INFINITY);  // not known
  std::vector<double> sigmas;
  for (long state : states) {
    const long index = std::lower_bound(order.begin(), order.end(), state) - order.begin();
    const double variance = solver.solve(Eigen::VectorXd::Unit(H.rows(), index))[index];
    sigmas.push_back(std::sqrt(std::max(variance, 1e-8)));
  }
  return sigmas;
}

void HeightFusion::settle(double stamp, long height, double sigma) {
  if (stamp <= settled_through_) return;  // settled already when the input ended once before
  settled_.push_back({stamp, states_.at(height), sigma});
  settled_through_ = stamp;
}

std::vector<SettledHeight> HeightFusion::take_settled(bool all) {
  if (all && !nodes_.empty() && nodes_.back().first > settled_through_) {
    solve();
    since_solve_ = 0;
    std::vector<long> window;
    for (const auto& [stamp, state] : nodes_) window.push_back(state);
    const std::vector<double> sigmas = marginal_sigmas(window);
    for (size_t i = 0; i < nodes_.size(); ++i) settle(nodes_[i].first, nodes_[i].second, sigmas[i]);
  }
  return std::exchange(settled_, {});
}

void HeightFusion::normal_equations(const std::vector<Linear>& residuals, const std::vector<long>& order,
                                    Eigen::SparseMatrix<double>& H, Eigen::VectorXd& g) const {
  const long n = static_cast<long>(order.size());
  std::unordered_map<long, long> index;
  index.reserve(order.size());
  for (long i = 0; i < n; ++i) index.emplace(order[i], i);
  Eigen::VectorXd x(n);
  for (long i = 0; i < n; ++i) x[i] = states_.at(order[i]);
  std::vector<Eigen::Triplet<double>>& terms = terms_;
  terms.clear();
  g = Eigen::VectorXd::Zero(n);
  std::vector<long> at;
  for (const auto& residual : residuals) {
    // A residual touches a few states: accumulate only their entries.
    const size_t m = residual.states.size();
    at.resize(m);
    double r = -residual.value;
    for (size_t i = 0; i < m; ++i) {
      at[i] = index.at(residual.states[i]);
      r += residual.coefficients[i] * x[at[i]];
    }
    r /= residual.sigma;
    double weight = 1.0;  // the Cauchy loss's derivative at r^2 (its weight in reweighted least squares)
    if (residual.cauchy > 0) weight = 1 / (1 + r * r / (residual.cauchy * residual.cauchy));
    for (size_t i = 0; i < m; ++i) {
      const double ji = residual.coefficients[i] / residual.sigma;
      g[at[i]] += weight * ji * r;
      for (size_t j = 0; j < m; ++j)
        terms.emplace_back(at[i], at[j], weight * ji * residual.coefficients[j] / residual.sigma);
    }
  }
  const long k = static_cast<long>(prior_.states.size());
  at.resize(k);
  Eigen::VectorXd moved(k);
  for (long i = 0; i < k; ++i) {
    at[i] = index.at(prior_.states[i]);
    moved[i] = x[at[i]] - prior_.at[i];
  }
  const Eigen::VectorXd prior_gradient = prior_.gradient + prior_.information * moved;
  for (long i = 0; i < k; ++i) {
    g[at[i]] += prior_gradient[i];
    for (long j = 0; j < k; ++j) terms.emplace_back(at[i], at[j], prior_.information(i, j));
  }
  for (long i = 0; i < n; ++i) terms.emplace_back(i, i, 1e-9);  // a state nothing constrains stays put
  H.resize(n, n);
  H.setFromTriplets(terms.begin(), terms.end());
}

// The residuals touching the dropped states, linearised at the current estimate, become
// one Gaussian prior on the states they share with the rest: H_kk - H_kd H_dd^-1 H_dk, the
// Schur complement, with its gradient. The previous prior joins them, so there is only
// ever one.
void HeightFusion::marginalise(const std::vector<long>& dropped) {
  const std::set<long> gone(dropped.begin(), dropped.end());
  std::vector<Linear> touching, kept;
  for (auto& residual : residuals_) {
    const bool touches =
        std::any_of(residual.states.begin(), residual.states.end(), [&](long s) { return gone.count(s); });
    (touches ? touching : kept).push_back(std::move(residual));
  }
  std::vector<long> order(dropped);  // dropped first, then the boundary
  std::set<long> listed(dropped.begin(), dropped.end());
  const auto list = [&](long s) {
    if (listed.insert(s).second) order.push_back(s);
  };
  for (const auto& residual : touching)
    for (long s : residual.states) list(s);
  for (long s : prior_.states) list(s);
  const long n = static_cast<long>(order.size()), d = static_cast<long>(dropped.size()), k = n - d;
  Eigen::SparseMatrix<double> sparse;
  Eigen::VectorXd g;
  normal_equations(touching, order, sparse, g);
  const Eigen::MatrixXd H(sparse);
  residuals_ = std::move(kept);
  for (long s : dropped) states_.erase(s);
  const Eigen::LDLT<Eigen::MatrixXd> solver(H.topLeftCorner(d, d));
  const Eigen::MatrixXd Hkd = H.bottomLeftCorner(k, d);
  prior_.information = H.bottomRightCorner(k, k) - Hkd * solver.solve(Hkd.transpose());
  prior_.gradient = g.tail(k) - Hkd * solver.solve(g.head(d));
  prior_.states.assign(order.begin() + d, order.end());
  prior_.at.resize(k);
  for (long i = 0; i < k; ++i) prior_.at[i] = states_.at(prior_.states[i]);
}

// Gauss-Newton, the robust residuals reweighted at each step (iteratively reweighted least
// squares with the Cauchy loss's weight): every residual is linear, so a few steps
// converge. Written here rather than handed to Ceres: with the elevation map's corners in
// the dense prior, Ceres's setup of the sparse normal equations at every solve cost 4.3 ms
// per update (pose_estimation_bench, 116 corners) against the 1 ms target; a sparse
// Cholesky of the same equations (Eigen, fill-reducing order) fills in only the corners.
void HeightFusion::solve() {
  constexpr int kMaxSteps = 3;
  constexpr double kConverged = 1e-4;  // m: the largest state change of a step
  std::vector<long> order;
  for (const auto& [state, value] : states_) order.push_back(state);
  Eigen::SparseMatrix<double> H;
  Eigen::VectorXd g;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
  for (int step = 0; step < kMaxSteps; ++step) {
    normal_equations(residuals_, order, H, g);
    if (step == 0) solver.analyzePattern(H);
    solver.factorize(H);
    if (solver.info() != Eigen::Success) return;
    const Eigen::VectorXd delta = solver.solve(-g);
    for (size_t i = 0; i < order.size(); ++i) states_.at(order[i]) += delta[static_cast<long>(i)];
    if (delta.cwiseAbs().maxCoeff() < kConverged) break;
  }
  // The newest height's marginal standard deviation: its diagonal entry of H^-1.
  const long newest = std::lower_bound(order.begin(), order.end(), nodes_.back().second) - order.begin();
  height_sigma_ = std::sqrt(std::max(0.0, solver.solve(Eigen::VectorXd::Unit(H.rows(), newest))[newest]));
}

double HeightFusion::height() const {
  return nodes_.empty() ? first_altitude_.value_or(0) : states_.at(nodes_.back().second);
}
double HeightFusion::bias() const { return biases_.empty() ? 0 : states_.at(biases_.back().second); }
size_t HeightFusion::ground_cells() const {
  size_t count = known_ground_.size();
  for (const auto& [cell, corner] : corners_) count += known_ground_.count(cell) == 0;
  return count;
}
size_t HeightFusion::nodes_in_window() const { return nodes_.size(); }

}  // namespace scanbus::pose_estimation
