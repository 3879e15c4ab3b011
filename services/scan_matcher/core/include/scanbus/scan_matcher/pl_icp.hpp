// PL-ICP (Censi, "An ICP variant using a point-to-line metric", ICRA 2008): each point of
// the new scan is matched to the line through its nearest reference point; the
// point-to-line errors are weighted by a robust kernel and minimised by Gauss-Newton. Unlike
// Censi's segment between two neighbouring points, the line is fitted to neighbours on each
// side spanning at least min_line_length: the two-point segment's direction drowns in range
// noise. The reference is a local map of the latest keyframes (scan-to-map matching: pairwise
// matches drift in heading), each map point keeping the line of the scan it came from.
#pragma once

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <vector>

#include "scanbus/config.hpp"
#include "scanbus/scan_matcher/pose2.hpp"
#include "scanbus/sensor/laser_scan.hpp"

namespace scanbus::scan_matcher {

struct MatcherSettings {
  double range_min = 0.05;          // m
  double range_max = 30.0;          // m: the MAV paper keeps ranges up to 30 m
  double opening = 2 * M_PI;        // rad kept around the scan's middle (the paper: 90 degrees)
  double max_correspondence = 0.5;  // m from a point to its reference point
  double max_segment_gap = 0.5;     // m between neighbouring reference points on one surface
  int line_neighbours = 4;          // the reference line at a point is fitted to this many
                                    // neighbours on each side (1: Censi's two-point segment);
                                    // with 2 cm noise and 0.5 degree rays two points give no
                                    // usable direction
  double min_line_length = 0.3;     // m: more neighbours join until the line spans this
  double trim = 1.0;                // share of correspondences kept, best first
  double robust_scale = 0.03;       // m: the kept correspondences weigh 1 / (1 + (error / scale)^2)
                                    // (Cauchy), so a surface that moved pulls little; 0: all weigh 1.
                                    // About twice a SICK LMS's systematic range error (15 mm)
  int max_iterations = 20;
  double epsilon = 1e-4;  // m and rad: converged when a step is smaller
  size_t min_correspondences = 30;
  double max_jump = 1.0;                // m per scan: a larger increment is a divergence
  double min_inlier_ratio = 0.5;        // a match explaining fewer points than this share of what the
                                        // recent matches explained is a wrong minimum: not taken
  int lost_after = 20;                  // this many failed matches in a row start the map again
  double prior_weight = 1.0;            // pull towards the prediction, per m (and rad) squared,
                                        // against one per correspondence: keeps unconstrained
                                        // directions (a corridor's length) at the prediction.
                                        // This one for constant velocity (no guess given)
  double guess_weight = 1.0;            // the same when the caller gave a motion guess to add_scan
                                        // (odometry; the node's IMU guess is the IMU's turn with
                                        // the last increment's translation, none without
                                        // constant_velocity; all pulled with this)
  double guess_jump = 0.3;              // m, and rad: a motion guess (odometry) this far from, or
  double guess_turn = 20 * M_PI / 180;  // turned this much from, the last taken increment is the
                                        // odometry jumping: more than an indoor robot's motion
                                        // changes between two scans
  bool constant_velocity = true;        // the prediction is the last increment again; false: no
                                        // motion, for a scanner whose motion in its scan plane
                                        // is small between scans (the MAV's downward laser): over
                                        // ground the scan constrains only across it, one wrong
                                        // match carried on slides the pose at every scan
  double suspicious_residual = 2.0;     // a residual this many times the recent ones makes the
                                        // matcher try other initial guesses
  double inlier_distance = 0.05;        // m: a point this close to its line counts as explained
  // The local map.
  double keyframe_distance = 0.5;  // m since the keyframe before a new one
  double keyframe_angle = 10 * M_PI / 180;
  int map_keyframes = 40;        // the map holds the points of this many latest keyframes: 20 m of
                                 // travel, over which a 1 degree scanner still resolves walls
  double map_resolution = 0.05;  // m: one map point per cell this wide (0: every point): the ray
                                 // spacing of a 0.5 degree scanner at 6 m
};

// Section `scan_matcher.matcher` of config/services/scan_matcher.yaml (angles in degrees
// there, radians here).
MatcherSettings matcher_settings_from_config(const Config& section);

enum class MatchQuality : uint8_t { Ok = 0, TooFewCorrespondences = 1, Diverged = 2, NoReference = 3, Ambiguous = 4 };

struct MatchResult {
  MatchQuality quality = MatchQuality::NoReference;
  Pose2 pose;                                            // cumulative, since the first scan
  Pose2 increment;                                       // since the previous scan
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of the match against the map (x, y, theta)
  int iterations = 0;
  size_t correspondences = 0;
  double residual = 0;    // m, mean |point-to-line error| of the kept correspondences
  size_t inliers = 0;     // correspondences within inlier_distance
  bool keyframe = false;  // this scan became a keyframe of the map
};

class ScanMatcher {
 public:
  explicit ScanMatcher(MatcherSettings settings = {});
  ~ScanMatcher();
  ScanMatcher(const ScanMatcher&) = delete;
  ScanMatcher& operator=(const ScanMatcher&) = delete;
  const MatcherSettings& settings() const { return settings_; }

  // Matches against the local map. `motion_guess` is the expected motion since the previous
  // scan (e.g. from odometry); without it, or when it jumps (guess_jump, guess_turn), the
  // previous increment is assumed again (constant velocity; no motion without
  // constant_velocity). A failed match follows that
  // prediction once and holds the pose after (or follows the guess when one was given);
  // lost_after failures in a row start the map again from the scan.
  MatchResult add_scan(const sensor::LaserScan& scan, const std::optional<Pose2>& motion_guess = std::nullopt);

  const Pose2& pose() const { return pose_; }
  size_t map_points() const;
  std::vector<Eigen::Vector2d> points_of(const sensor::LaserScan& scan) const;

  // One PL-ICP alignment of `scan` to `reference` from `guess` (the scan's pose in the
  // reference frame), without a map, pulled towards the guess with prior_weight.
  MatchResult align(const std::vector<Eigen::Vector2d>& reference, const std::vector<Eigen::Vector2d>& scan,
                    const Pose2& guess) const;

 private:
  struct Keyframe;
  struct Reference;
  class LocalMap;
  Reference reference_of(const std::vector<Eigen::Vector2d>& points) const;
  // Where the motion says the scan was taken (in the reference frame), and how firmly.
  struct Prior {
    Pose2 pose;
    double weight;
  };
  // Gauss-Newton from `guess`, weakly pulled towards the prior.
  MatchResult align_to(const Reference& reference, const std::vector<Eigen::Vector2d>& scan, const Pose2& guess,
                       const Prior& prior) const;
  double cauchy_weight(double error) const {
    if (settings_.robust_scale <= 0) return 1;
    const double ratio = error / settings_.robust_scale;
    return 1 / (1 + ratio * ratio);
  }
  std::optional<Pose2> plausible(const std::optional<Pose2>& guess) const;
  void judge(MatchResult& result, const Pose2& increment, size_t points);
  MatchResult best_alignment(const std::vector<Eigen::Vector2d>& points,
                             const std::optional<Pose2>& motion_guess) const;
  void add_keyframe(std::vector<Eigen::Vector2d> points);

  MatcherSettings settings_;
  std::optional<Pose2> keyframe_pose_;  // of the latest keyframe; none before a usable scan
  std::unique_ptr<LocalMap> map_;       // in the first scan's frame
  Pose2 pose_;
  Pose2 last_increment_;             // the prediction: the last taken increment, zero after a failure
                                     // (always, without constant_velocity)
  Pose2 last_taken_;                 // the last taken increment, which a guess is judged against
  double typical_residual_ = 0;      // m, running mean of accepted matches' residuals
  int failures_ = 0;                 // failed matches in a row
  double typical_inlier_share_ = 0;  // running mean of accepted matches' inliers per point
};

}  // namespace scanbus::scan_matcher
