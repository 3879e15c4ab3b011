// PL-ICP (Censi, "An ICP variant using a point-to-line metric", ICRA 2008): each point of
// the new scan is matched to the line through its nearest reference point; the
// point-to-line errors are trimmed and minimised by Gauss-Newton. Unlike Censi's segment
// between two neighbouring points, the line is fitted to neighbours on each side spanning
// at least min_line_length: the two-point segment's direction drowns in range noise. The
// reference is a keyframe (or the latest few), renewed after enough motion.
#pragma once

#include <Eigen/Core>

#include <deque>
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
  double trim = 0.9;                // share of correspondences kept, best first
  int max_iterations = 20;
  double epsilon = 1e-4;  // m and rad: converged when a step is smaller
  size_t min_correspondences = 30;
  double max_jump = 1.0;           // m per scan: a larger increment is a divergence
  double keyframe_distance = 0.1;  // m since the keyframe before a new one
  double keyframe_angle = 10 * M_PI / 180;
  double prior_weight = 1.0;         // pull towards the initial guess, per m (and rad) squared,
                                     // against one per correspondence: keeps unconstrained
                                     // directions (a corridor's length) at the prediction
  double suspicious_residual = 2.0;  // a residual this many times the recent ones makes the
                                     // matcher try other initial guesses
  double inlier_distance = 0.05;     // m: a point this close to its line counts as explained
  int map_keyframes = 1;             // the reference is the union of this many latest keyframes
};

// Section `scan_matcher.matcher` of config/services/scan_matcher.yaml (angles in degrees
// there, radians here).
MatcherSettings matcher_settings_from_config(const Config& section);

enum class MatchQuality : uint8_t { Ok = 0, TooFewCorrespondences = 1, Diverged = 2, NoReference = 3 };

struct MatchResult {
  MatchQuality quality = MatchQuality::NoReference;
  Pose2 pose;                                            // cumulative, since the first scan
  Pose2 increment;                                       // since the previous scan
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of the match against the keyframe (x, y, theta)
  int iterations = 0;
  size_t correspondences = 0;
  double residual = 0;    // m, mean |point-to-line error| of the kept correspondences
  size_t inliers = 0;     // correspondences within inlier_distance
  bool keyframe = false;  // this scan is the new reference
};

class ScanMatcher {
 public:
  explicit ScanMatcher(MatcherSettings settings = {});
  ~ScanMatcher();
  ScanMatcher(const ScanMatcher&) = delete;
  ScanMatcher& operator=(const ScanMatcher&) = delete;

  // Matches against the keyframe. `motion_guess` is the expected motion since the previous
  // scan (e.g. from odometry); without it the previous increment is assumed again. A
  // failed match holds the pose (or follows the guess when one was given).
  MatchResult add_scan(const sensor::LaserScan& scan, const std::optional<Pose2>& motion_guess = std::nullopt);

  const Pose2& pose() const { return pose_; }
  std::vector<Eigen::Vector2d> points_of(const sensor::LaserScan& scan) const;

  // One PL-ICP alignment of `scan` to `reference` from `guess` (the scan's pose in the
  // reference frame); for BacktransformLaserScan and tests.
  MatchResult align(const std::vector<Eigen::Vector2d>& reference, const std::vector<Eigen::Vector2d>& scan,
                    const Pose2& guess) const;

  // BacktransformLaserScan's check, as numbers: |point-to-line distance| of each point of
  // `scan` placed at `pose` to the reference's local line at its nearest point (points with
  // no reference point within max_correspondence, or no line there, are left out).
  std::vector<double> residuals(const std::vector<Eigen::Vector2d>& reference, const std::vector<Eigen::Vector2d>& scan,
                                const Pose2& pose) const;

 private:
  struct Keyframe;
  struct Reference;
  // Gauss-Newton from `guess`, weakly pulled towards `prior` (both in the reference frame).
  MatchResult align_to(const Reference& reference, const std::vector<Eigen::Vector2d>& scan, const Pose2& guess,
                       const Pose2& prior) const;
  MatchResult best_alignment(const std::vector<Eigen::Vector2d>& points,
                             const std::optional<Pose2>& motion_guess) const;
  void add_keyframe(std::vector<Eigen::Vector2d> points);

  MatcherSettings settings_;
  std::deque<std::unique_ptr<Keyframe>> keyframes_;  // oldest first
  std::unique_ptr<Reference> map_;                   // the keyframes' points in the first scan's frame
  Pose2 pose_;
  Pose2 last_increment_;
  double typical_residual_ = 0;  // m, running mean of accepted matches' residuals
};

}  // namespace scanbus::scan_matcher
