// The MAV's height by least squares over a sliding window (Ceres), after section 3.6 of
// the MAV paper: the paper starts from the barometer and adds the scan matcher's height
// changes; here every barometer sample (with a slowly wandering bias) and every
// scan-matcher change enter one problem, the changes under a robust loss so a failed match
// is outvoted instead of integrated.
//
// Those two alone cannot hold the height: the barometer's bias and the integrated changes
// both wander, and nothing tells one wander from the other, so their best combination
// still wanders (for the simulator's noise by about 0.013 m/sqrt(s), 0.12 m RMS over a
// 3-minute flight; docs/performance.md). What pins the height down is the ground itself: each scan's ground
// clearance (laser_height.hpp) is the height above a ground level, a state shared by every
// scan that sees ground at that height (the floor, a block's top), so over ground seen before
// the height cannot drift. A level's absolute height, like the MAV's, comes from the
// barometer. States leaving the window are marginalised (Schur
// complement) into a prior on those that stay, so nothing the window forgot is either
// lost or counted twice. GPS altitude stays out: its error wanders over minutes, and taken
// as independent fixes it outweighed the barometer (scenario I: 0.71 m RMSE with it,
// 0.18 m without; docs/performance.md).
#pragma once

#include <Eigen/Core>

#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <vector>
#include <cstdint>

namespace scanbus::pose_estimation {

struct FusionSettings {
  double window = 3.0;              // s of nodes kept in the problem
  double baro_sigma = 0.3;          // m, white noise of one barometer altitude
  double baro_gate_time = 10.0;     // s: a barometer altitude 5 sigma (its own and the
                                    // estimate's) off the estimate (a gust,
                                    // a door, a fault) is counted and left out, unless the
                                    // barometer has been that far off for this long: a shift
                                    // that persists is believed (the only absolute height)
  double bias_random_walk = 0.02;   // m/sqrt(s): how fast the barometer's bias wanders
  double bias_spacing = 1.0;        // s between bias states (linear in between)
  double initial_bias_sigma = 0.05; // m: the barometer is referenced on the ground at the start
  double change_sigma = 0.003;      // m, one scan-matcher height change (measured on the
                                    // simulated flights: 2-3 mm between scans at 30 Hz)
  double change_loss = 0.005;       // m: Cauchy scale; far larger disagreements count little
  double change_gate = 0.05;        // m: a change this far from the previous accepted one (a
                                    // velocity jump of 1.5 m/s between scans at 30 Hz) is a
                                    // failed match, left out before it can pull the window into
                                    // a wrong minimum of the robust loss
  double height_walk = 0.2;         // m/sqrt(s): the height's random walk between nodes without a change
  double gate_memory = 0.5;         // s: after this long without an accepted change, any is accepted
  int solve_every = 3;              // nodes between solves (the newest node is propagated in between)
  double clearance_sigma = 0.01;    // m, one ground clearance (line fit, attitude, rough ground)
  double clearance_loss = 0.03;     // m: Cauchy scale; a wrong line or level counts little
  double level_gate = 0.25;         // m: ground further than this from every known level is a new one
  int max_levels = 16;              // the least recently seen beyond these is marginalised
};

class HeightFusion {
 public:
  explicit HeightFusion(FusionSettings settings = {});
  ~HeightFusion();
  HeightFusion(const HeightFusion&) = delete;
  HeightFusion& operator=(const HeightFusion&) = delete;

  // Altitude above the map origin (m). Samples wait until nodes on both sides exist.
  void add_barometer(double stamp, double altitude);

  // A node at `stamp` (after the previous one) with the scan matcher's height change since
  // the previous node, or none (failed match, no scan matcher), and the height above the
  // ground the scan saw, or none. Returns the height now estimated for this node. The first
  // node starts at the first barometer altitude.
  double add_node(double stamp, std::optional<double> change, std::optional<double> clearance = std::nullopt);

  // Barometer altitudes more than 5 sigma from the estimate when they entered (left out
  // unless the barometer has been off for baro_gate_time).
  uint64_t barometer_outliers() const { return barometer_outliers_; }
  double height() const;                        // of the newest node
  bool has_barometer() const { return first_altitude_.has_value(); }
  double bias() const;                          // the barometer's, at the newest node
  size_t ground_levels() const { return levels_.size(); }
  double height_sigma() const { return height_sigma_; }  // m, of the newest node at the last solve
  size_t nodes_in_window() const;
  uint64_t changes_rejected() const { return changes_rejected_; }

 private:
  // Every residual here is linear in the states: (sum coefficient * state - value) / sigma,
  // under a Cauchy loss of scale `cauchy` (in sigmas) when that is not 0: height changes
  // (failed matches) and clearances (wrong lines).
  struct Linear {
    std::vector<long> states;
    std::vector<double> coefficients;
    double value, sigma;
    double cauchy = 0;
    bool prior = false;  // a row of the marginalisation prior
  };
  struct Sample {  // a barometer altitude
    double stamp, value, sigma;
  };
  long new_state(double initial);
  void add_sample_residual(const Sample& sample);
  void add_clearance(double stamp, long height, double clearance);
  void solve();
  void slide();
  void marginalise(const std::vector<long>& dropped);
  // Gauss-Newton normal equations (H, g) of `residuals` over the states in `order`, at the
  // current estimate, robust residuals with the weight their loss gives them there.
  void normal_equations(const std::vector<Linear>& residuals, const std::vector<long>& order, Eigen::MatrixXd& H,
                        Eigen::VectorXd& g) const;

  FusionSettings settings_;
  std::map<long, double> states_;               // stable addresses for Ceres
  long next_state_ = 0;
  std::deque<std::pair<double, long>> nodes_;   // stamp, height state
  std::deque<std::pair<double, long>> biases_;  // stamp, bias state
  struct Level {
    long state;
    double seen;  // stamp of its newest clearance
  };
  std::vector<Level> levels_;
  std::vector<Linear> residuals_;
  std::vector<Sample> pending_;                 // newer than the newest node
  std::optional<double> first_altitude_;
  uint64_t barometer_outliers_ = 0;
  std::optional<double> barometer_off_since_;
  int since_solve_ = 0;
  double height_sigma_ = 0;
  std::optional<std::pair<double, double>> last_change_;  // stamp, value of the last accepted change
  uint64_t changes_rejected_ = 0;
};

}  // namespace scanbus::pose_estimation
