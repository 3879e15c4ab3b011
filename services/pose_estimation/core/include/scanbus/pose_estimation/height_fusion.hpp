// The MAV's height and the ground under it by least squares over a sliding window,
// after section 3.6 of the MAV paper: the paper starts from the barometer and adds the scan
// matcher's height changes; here every barometer sample, every GPS altitude (each with a
// slowly wandering bias), every scan-matcher change and the ground each scan sees enter one
// problem, the laser's terms under robust losses so a failed match or a box is outvoted.
//
// The laser does not measure height: it measures the height above the ground under the
// scan, and over a slope or a mound the ground moves too. So the ground is estimated with
// the height: a 2.5D elevation map of corners `cell_size` apart, heights interpolated
// bilinearly between them (no assumption of level or piecewise flat ground). Each scan's
// returns in a cell give `height - ground(xy) = depth`; the scan matcher's change is the
// change of that depth, so it carries the height only where the scans saw no ground.
// Ground seen again on a later pass ties the heights at both times; absolute
// height comes from the barometer and GPS (their biases as states, GPS weighted by the
// fix's own sigma) and from the map origin, whose ground is at the origin's altitude.
//
// States leaving the window are marginalised (Schur complement) into a prior on those that
// stay, the corners among them: ground seen minutes ago still ties the height. Beyond
// max_corners, the least recently seen corners are marginalised too and kept in a map of
// heights and standard deviations; seen again, such a corner restarts from that height with
// that sigma. That reuses what the prior already holds of it (an approximation, as in
// map-based localisation), the price of a problem that does not grow with the area flown.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "scanbus/pose_estimation/laser_height.hpp"

namespace scanbus::pose_estimation {

// The noise each default assumes comes from the sensors' data sheets and what flying does to
// them (docs/architecture.md, "What the fusion's defaults assume"), never from the simulator's
// settings, which model the world apart (services/mav_sim).
struct FusionSettings {
  double window = 3.0;                 // s of nodes kept in the problem
  double baro_sigma = 0.3;             // m, white noise of one barometer altitude: an MS5611 class
                                       // sensor resolves 0.1 m; the propellers' wash and gusts add
                                       // a few decimetres in flight
  double baro_gate_time = 10.0;        // s: a barometer altitude 5 sigma (its own and the
                                       // estimate's) off the estimate (a gust,
                                       // a door, a fault) is counted and left out, unless the
                                       // barometer has been that far off for this long: a shift
                                       // that persists is believed (the only absolute height)
  double bias_random_walk = 0.02;      // m/sqrt(s): how fast the barometer's bias wanders (the sensor
                                       // warming in flight, the weather: decimetres over minutes)
  double bias_spacing = 1.0;           // s between bias states (linear in between)
  double initial_bias_sigma = 0.3;     // m: the barometer is referenced on the ground before take-off,
                                       // then the spinning propellers and the ground effect shift it by
                                       // decimetres (autopilots carry a ground-effect dead zone for it)
  double gps_wander_time = 30.0;       // s: a fix's altitude is off by the sigma the receiver
                                       // reports, an error correlated over this time
  double change_sigma = 0.003;         // m, one scan-matcher height change: hundreds of returns of a
                                       // few centimetres' range noise each pin it to millimetres
  double change_loss = 0.005;          // m: Cauchy scale; far larger disagreements count little
  double change_gate = 0.05;           // m: a change this far from the previous accepted one (a
                                       // velocity jump of 1.5 m/s between scans at 30 Hz) is a
                                       // failed match, left out before it can pull the window into
                                       // a wrong minimum of the robust loss
  double height_walk = 0.2;            // m/sqrt(s): the height's random walk between nodes without a change
  double gate_memory = 0.5;            // s: after this long without an accepted change, any is accepted
  int solve_every = 3;                 // nodes between solves (the newest node is propagated in between)
  double cell_size = 1.0;              // m between the elevation map's corners
  int min_cell_returns = 5;            // returns of one scan in a cell before it says where the ground is
  double clearance_sigma = 0.02;       // m, the depth of one cell's ground under one scan (the median
                                       // of its returns: each of a few centimetres' range noise, moved
                                       // by the attitude's few tenths of a degree; relief finer than a cell)
  double clearance_loss = 0.05;        // m: Cauchy scale; a box or a stone in a cell counts little
  double clearance_gate = 0.15;        // m: a cell's ground this far (or 5 sigma of the height) from
                                       // where the map puts it is a step or an edge inside the cell,
                                       // which corners cannot follow: left out
  double ground_gradient_sigma = 1.0;  // m per m between neighbouring corners: a weak tie that only
                                       // decides what the returns leave open
  int max_corners = 200;               // kept in the problem (the prior is dense over them: a solve's
                          // cost grows with their cube; 200 at 1 m: 0.2 ha); beyond, the least recently seen
                          // leave with their height and sigma, and a corner seen again
                          // restarts from them
  bool origin_on_ground = true;  // the ground at the map origin is at the origin's altitude
  double origin_sigma = 0.05;    // m: how well (rough ground, where the origin was taken)
};

// A node's height as it left the window: solved with every sample of the `window` seconds
// after it (a fixed-lag smoother's output), with its marginal standard deviation then.
struct SettledHeight {
  double stamp = 0, height = 0, sigma = 0;  // s, m, m
};

class HeightFusion {
 public:
  explicit HeightFusion(FusionSettings settings = {});
  ~HeightFusion();
  HeightFusion(const HeightFusion&) = delete;
  HeightFusion& operator=(const HeightFusion&) = delete;

  // Altitude above the map origin (m). Samples wait until nodes on both sides exist.
  void add_barometer(double stamp, double altitude);
  // A GPS altitude above the map origin (m) with the vertical sigma its fix reports (a fix
  // without a positive sigma cannot be weighed and is left out).
  void add_gps(double stamp, double altitude, double vertical_sigma);

  // A node at `stamp` (after the previous one) with the scan matcher's height change since
  // the previous node, or none (failed match, no scan matcher), and the scan's returns on
  // the ground. Returns the height now estimated for this node. The first node starts at the
  // first barometer altitude and is solved at once when a barometer or GPS altitude ties it.
  double add_node(double stamp, std::optional<double> change, const std::vector<GroundReturn>& ground = {});

  // The heights of the nodes that left the window since the last call, oldest first (each
  // node once). With `all` (the input has ended) also those still in it, solved now.
  std::vector<SettledHeight> take_settled(bool all = false);

  // Barometer altitudes more than 5 sigma from the estimate when they entered (left out
  // unless the barometer has been off for baro_gate_time).
  uint64_t barometer_outliers() const { return barometer_outliers_; }
  double height() const;  // of the newest node
  bool has_barometer() const { return first_altitude_.has_value(); }
  double bias() const;                                   // the barometer's, at the newest node
  size_t ground_cells() const;                           // corners of the elevation map estimated so far
  double height_sigma() const { return height_sigma_; }  // m, of the newest node at the last solve
  size_t nodes_in_window() const;
  uint64_t changes_rejected() const { return changes_rejected_; }
  uint64_t cells_gated() const { return cells_gated_; }  // a scan's cells left out (clearance_gate)

 private:
  // Every residual here is linear in the states: (sum coefficient * state - value) / sigma,
  // under a Cauchy loss of scale `cauchy` (in sigmas) when that is not 0: height changes
  // (failed matches) and clearances (boxes, edges).
  struct Linear {
    std::vector<long> states;
    std::vector<double> coefficients;
    double value, sigma;
    double cauchy = 0;
  };
  // What marginalised states left on those that stay: the cost's gradient and Hessian there
  // at the estimate `at` (the quadratic 1/2 dx' information dx + gradient' dx).
  struct Prior {
    std::vector<long> states;
    Eigen::MatrixXd information;
    Eigen::VectorXd gradient, at;
  };
  struct Sample {  // a barometer or GPS altitude
    double stamp, value, sigma;
  };
  using Chain = std::deque<std::pair<double, long>>;  // stamp, state: heights or biases, in time
  using Cell = std::pair<long, long>;                 // a corner's index along x and y
  struct Corner {
    long state;
    double seen;  // stamp of the newest scan that saw it
  };
  struct KnownGround {
    double height, sigma;
  };
  long new_state(double initial);
  void extend(Chain& biases, double stamp, double initial_sigma, double step_sigma, double decay = 1);
  Linear interpolated(const Sample& sample, const Chain& biases) const;
  void add_barometer_residual(const Sample& sample);
  bool add_ground(double stamp, long height, const std::vector<GroundReturn>& ground);
  long corner(const Cell& cell, double stamp, double initial);
  void solve();
  void slide();
  void marginalise(const std::vector<long>& dropped);
  // Each state's marginal standard deviation (its diagonal entry of H^-1) at the estimate.
  std::vector<double> marginal_sigmas(const std::vector<long>& states) const;
  void settle(double stamp, long height, double sigma);
  // Gauss-Newton normal equations (H, g) of `residuals` and the prior over the states in
  // `order` (all the prior's among them), at the current estimate, robust residuals with the
  // weight their loss gives them there.
  void normal_equations(const std::vector<Linear>& residuals, const std::vector<long>& order,
                        Eigen::SparseMatrix<double>& H, Eigen::VectorXd& g) const;

  FusionSettings settings_;
  std::map<long, double> states_;  // by state index
  long next_state_ = 0;
  Chain nodes_;                               // heights
  Chain biases_;                              // the barometer's
  Chain gps_biases_;                          // the GPS altitude's
  std::map<Cell, Corner> corners_;            // the elevation map's corners in the problem
  std::map<Cell, KnownGround> known_ground_;  // corners marginalised, as last estimated
  bool previous_saw_ground_ = false;
  std::vector<Linear> residuals_;
  Prior prior_;
  mutable std::vector<Eigen::Triplet<double>> terms_;  // normal_equations' buffer, kept: its size
                                                       // would otherwise be mapped anew each time
  std::vector<Sample> pending_, pending_gps_;          // newer than the newest node
  std::optional<double> gps_sigma_;                    // the newest fix's
  uint64_t cells_gated_ = 0;
  std::optional<double> first_altitude_;
  uint64_t barometer_outliers_ = 0;
  std::optional<double> barometer_off_since_;
  int since_solve_ = 0;
  double height_sigma_ = 0;
  std::optional<std::pair<double, double>> last_change_;  // stamp, value of the last accepted change
  uint64_t changes_rejected_ = 0;
  std::vector<SettledHeight> settled_;  // until take_settled
  double settled_through_ = -1e300;     // stamp of the newest node settled
};

}  // namespace scanbus::pose_estimation
