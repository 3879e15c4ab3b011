#include "scanbus/scan_matcher/pl_icp.hpp"

#include "nearest_points.hpp"
#include "scanbus/scan_matcher/backtransform.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "scanbus/units.hpp"

namespace scanbus::scan_matcher {

namespace {

struct Correspondence {
  size_t point;
  Eigen::Vector2d normal;
  double error;
};

// The line through a reference point: total least squares over its neighbours in scan
// order that lie on the same surface (no gap wider than max_gap between consecutive ones).
struct LocalLine {
  bool valid = false;
  Eigen::Vector2d centre, normal;
};

constexpr double kMaxLineSpread = 0.3;  // smallest over largest eigenvalue of a neighbourhood

std::vector<LocalLine> local_lines(const std::vector<Eigen::Vector2d>& points, int neighbours, double min_length,
                                   double max_gap) {
  std::vector<LocalLine> lines(points.size());
  const long count = static_cast<long>(points.size());
  // Dense rays (close surfaces, fine resolution) need more neighbours for a line long
  // enough that range noise does not turn it: grow until min_length is spanned.
  const long most = 8 * static_cast<long>(neighbours);
  for (long i = 0; i < count; ++i) {
    long low = i, high = i;
    auto step_down = [&] { return low > 0 && (points[low - 1] - points[low]).norm() <= max_gap; };
    auto step_up = [&] { return high + 1 < count && (points[high + 1] - points[high]).norm() <= max_gap; };
    while (i - low < neighbours && step_down()) --low;
    while (high - i < neighbours && step_up()) ++high;
    while ((points[high] - points[low]).norm() < min_length && high - low < 2 * most && (step_down() || step_up())) {
      if (step_down()) --low;
      if (step_up()) ++high;
    }
    if (high - low < 1) continue;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (long j = low; j <= high; ++j) centre += points[j];
    centre /= static_cast<double>(high - low + 1);
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (long j = low; j <= high; ++j) scatter += (points[j] - centre) * (points[j] - centre).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver;
    solver.computeDirect(scatter);  // closed form for 2x2
    // Not line-like (a corner, a pillar's edge): no trustworthy direction.
    if (solver.eigenvalues()(0) > kMaxLineSpread * solver.eigenvalues()(1)) continue;
    lines[i] = {true, centre, solver.eigenvectors().col(0)};
  }
  return lines;
}

}  // namespace

struct ScanMatcher::Keyframe {
  Keyframe(const Pose2& pose, std::vector<Eigen::Vector2d> scan_points, const MatcherSettings& settings)
      : pose(pose),
        points(std::move(scan_points)),
        lines(local_lines(points, settings.line_neighbours, settings.min_line_length, settings.max_segment_gap)) {}
  Pose2 pose;  // where the scan was taken
  std::vector<Eigen::Vector2d> points;
  std::vector<LocalLine> lines;
};

// Points and their local lines in one frame, with a k-d tree over the points.
struct ScanMatcher::Reference {
  Reference(std::vector<Eigen::Vector2d> points, std::vector<LocalLine> reference_lines)
      : search(std::move(points)), lines(std::move(reference_lines)) {}
  NearestPoints search;
  std::vector<LocalLine> lines;
};

// The local map: keyframes' points in the first scan's frame, thinned to one point per cell
// of map_resolution (the first seen stays: older points anchor the newer ones against drift),
// each with the line of the scan it came from (the lines come from each scan's own ray order,
// cheaper and steadier than fitting them to map neighbours). A point leaves with its keyframe
// once that is older than the latest map_keyframes, and the keyframe coming in fills the cells
// it sees again, so memory and the search stay bounded wherever the sensor goes. (Keeping a
// cell as long as any kept keyframe sees it was measured worse on both Freiburg logs: it keeps
// far, noisy first sightings; docs/performance.md.)
class ScanMatcher::LocalMap {
 public:
  LocalMap(int keyframes, double resolution) : keyframes_(keyframes), resolution_(resolution) {}

  void insert(const Keyframe& keyframe) {
    ++serial_;
    expire(serial_ - keyframes_ + 1);  // first: a cell it leaves empty, this keyframe may fill
    const std::vector<Eigen::Vector2d> points = carried_back(keyframe.points, keyframe.pose);
    const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(keyframe.pose.theta).toRotationMatrix();
    for (size_t i = 0; i < points.size(); ++i) {
      if (!new_cell(points[i])) continue;
      LocalLine line = keyframe.lines[i];
      line.centre = rotation * line.centre + Eigen::Vector2d(keyframe.pose.x, keyframe.pose.y);
      line.normal = rotation * line.normal;
      entries_.push_back({points[i], line, serial_});
    }
    std::vector<Eigen::Vector2d> map_points;
    std::vector<LocalLine> lines;
    map_points.reserve(entries_.size());
    lines.reserve(entries_.size());
    for (const Entry& entry : entries_) {
      map_points.push_back(entry.point);
      lines.push_back(entry.line);
    }
    reference_ = std::make_unique<Reference>(std::move(map_points), std::move(lines));
  }

  const Reference& reference() const { return *reference_; }
  size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    Eigen::Vector2d point;
    LocalLine line;
    long serial;  // of the keyframe that brought it
  };

  // A resolution of 0 keeps every point.
  bool new_cell(const Eigen::Vector2d& point) { return resolution_ <= 0 || cells_.insert(cell_of(point)).second; }
  uint64_t cell_of(const Eigen::Vector2d& point) const {
    const auto index = [&](double value) {
      return static_cast<uint64_t>(static_cast<int64_t>(std::floor(value / resolution_)) & 0xffffffff);
    };
    return index(point.x()) << 32 | index(point.y());
  }

  // The entries are in the order their keyframes came: the expired ones lead.
  void expire(long oldest) {
    const auto kept =
        std::find_if(entries_.begin(), entries_.end(), [&](const Entry& entry) { return entry.serial >= oldest; });
    if (resolution_ > 0)  // each cell holds one entry: the expired entries' cells are free again
      for (auto entry = entries_.begin(); entry != kept; ++entry) cells_.erase(cell_of(entry->point));
    entries_.erase(entries_.begin(), kept);
  }

  const int keyframes_;
  const double resolution_;
  std::vector<Entry> entries_;
  std::unordered_set<uint64_t> cells_;  // those holding an entry
  long serial_ = 0;
  std::unique_ptr<Reference> reference_;
};

ScanMatcher::ScanMatcher(MatcherSettings settings)
    : settings_(settings), map_(std::make_unique<LocalMap>(settings.map_keyframes, settings.map_resolution)) {}
ScanMatcher::~ScanMatcher() = default;

size_t ScanMatcher::map_points() const { return map_->size(); }

ScanMatcher::Reference ScanMatcher::reference_of(const std::vector<Eigen::Vector2d>& points) const {
  return Reference(
      points, local_lines(points, settings_.line_neighbours, settings_.min_line_length, settings_.max_segment_gap));
}

std::vector<Eigen::Vector2d> ScanMatcher::points_of(const sensor::LaserScan& scan) const {
  return sensor::kept_points(scan, {settings_.range_min, settings_.range_max, settings_.opening});
}

MatchResult ScanMatcher::align(const std::vector<Eigen::Vector2d>& reference, const std::vector<Eigen::Vector2d>& scan,
                               const Pose2& guess) const {
  return align_to(reference_of(reference), scan, guess, {guess, settings_.prior_weight});
}

MatchResult ScanMatcher::align_to(const Reference& reference, const std::vector<Eigen::Vector2d>& scan,
                                  const Pose2& guess, const Prior& prior) const {
  MatchResult result;
  if (reference.search.points().size() < 2) {
    result.quality = MatchQuality::TooFewCorrespondences;
    return result;
  }
  Eigen::Vector3d x(guess.x, guess.y, guess.theta);
  std::vector<Correspondence> matches;
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
  std::vector<MovingQuery> nearest(scan.size());
  for (result.iterations = 1; result.iterations <= settings_.max_iterations; ++result.iterations) {
    const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(x[2]).toRotationMatrix();
    matches.clear();
    for (size_t i = 0; i < scan.size(); ++i) {
      const Eigen::Vector2d q = rotation * scan[i] + x.head<2>();
      const size_t found = nearest[i].nearest(reference.search, q, settings_.max_correspondence).index;
      if (found == NearestPoints::npos) continue;
      const LocalLine& line = reference.lines[found];
      if (!line.valid) continue;
      matches.push_back({i, line.normal, line.normal.dot(q - line.centre)});
    }
    result.inliers = static_cast<size_t>(std::count_if(
        matches.begin(), matches.end(), [&](const auto& m) { return std::abs(m.error) < settings_.inlier_distance; }));
    if (matches.size() < settings_.min_correspondences) {
      result.quality = MatchQuality::TooFewCorrespondences;
      break;
    }
    // Trimming: the worst matches are outliers (moved objects, new surfaces).
    const size_t keep = std::max(settings_.min_correspondences,
                                 static_cast<size_t>(settings_.trim * static_cast<double>(matches.size())));
    if (keep < matches.size()) {
      std::nth_element(matches.begin(), matches.begin() + static_cast<long>(keep - 1), matches.end(),
                       [](const auto& a, const auto& b) { return std::abs(a.error) < std::abs(b.error); });
      matches.resize(keep);
    }
    // Gauss-Newton on e_i = n_i . (R(theta) q_i + t - p_i).
    hessian.setZero();
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    double error_sum = 0;
    const double c = std::cos(x[2]), s = std::sin(x[2]);
    for (const auto& m : matches) {
      const Eigen::Vector2d& q = scan[m.point];
      const Eigen::Vector2d turned(-s * q.x() - c * q.y(), c * q.x() - s * q.y());  // dR/dtheta q
      const Eigen::Vector3d jacobian(m.normal.x(), m.normal.y(), m.normal.dot(turned));
      const double weight = cauchy_weight(m.error);
      hessian += weight * jacobian * jacobian.transpose();
      gradient += weight * jacobian * m.error;
      error_sum += std::abs(m.error);
    }
    // A weak pull towards the prior: along a corridor, where the walls leave the motion
    // unconstrained, the pose keeps the prediction instead of sliding.
    const Pose2& predicted = prior.pose;
    const Eigen::Vector3d from_guess(x[0] - predicted.x, x[1] - predicted.y, Pose2::normalize(x[2] - predicted.theta));
    const Eigen::Vector3d step =
        (hessian + prior.weight * Eigen::Matrix3d::Identity()).ldlt().solve(-(gradient + prior.weight * from_guess));
    if (!step.allFinite()) {
      result.quality = MatchQuality::Diverged;
      break;
    }
    x += step;
    x[2] = Pose2::normalize(x[2]);
    result.correspondences = matches.size();
    result.residual = error_sum / static_cast<double>(matches.size());
    result.quality = MatchQuality::Ok;
    if (step.head<2>().norm() < settings_.epsilon && std::abs(step[2]) < settings_.epsilon) break;
  }
  result.iterations = std::min(result.iterations, settings_.max_iterations);
  result.increment = {x[0], x[1], x[2]};
  if (result.quality == MatchQuality::Ok) {
    // The kernel's weights count as the correspondences they leave: an outlier adds no variance.
    double squares = 0, weights = 0;
    for (const auto& m : matches) {
      const double weight = cauchy_weight(m.error);
      squares += weight * m.error * m.error;
      weights += weight;
    }
    const double variance = squares / std::max(1.0, weights - 3);
    // From the scan alone (without the prior), so an unconstrained direction shows as one.
    result.covariance = variance * (hessian + 1e-9 * Eigen::Matrix3d::Identity()).inverse();
  }
  return result;
}

MatchResult ScanMatcher::add_scan(const sensor::LaserScan& scan, const std::optional<Pose2>& guess) {
  std::vector<Eigen::Vector2d> points = points_of(scan);
  const bool usable = points.size() >= settings_.min_correspondences;  // could start a map
  if (!keyframe_pose_) {
    MatchResult first;
    first.quality = MatchQuality::NoReference;
    first.pose = pose_;
    first.keyframe = usable;
    if (usable) add_keyframe(std::move(points));
    return first;
  }
  const std::optional<Pose2> motion_guess = plausible(guess);
  MatchResult result = best_alignment(points, motion_guess);
  const Pose2 previous = pose_;
  const Pose2 matched = result.increment;  // align_to's result is the pose in the map frame
  judge(result, previous.inverse() * matched, points.size());
  const bool ok = result.quality == MatchQuality::Ok;
  if (ok) {
    pose_ = matched;
    failures_ = 0;
  } else {
    // A failed match follows the prediction once; after that the pose is held unless a
    // guess (odometry) says otherwise: a velocity kept up blindly takes the pose away.
    pose_ = pose_ * motion_guess.value_or(last_increment_);
    ++failures_;
  }
  result.increment = previous.inverse() * pose_;
  last_increment_ = ok && settings_.constant_velocity ? result.increment : Pose2{};
  if (ok) last_taken_ = result.increment;
  result.pose = pose_;
  const Pose2 from_keyframe = keyframe_pose_->inverse() * pose_;
  if (failures_ >= settings_.lost_after && usable) {
    // Lost: the map no longer explains the scans. It starts again here rather than hold a
    // pose, or follow a guess, against a map that will never match.
    map_ = std::make_unique<LocalMap>(settings_.map_keyframes, settings_.map_resolution);
    failures_ = 0;
    typical_residual_ = typical_inlier_share_ = 0;  // of a place left behind
  } else if (!ok || (from_keyframe.distance() <= settings_.keyframe_distance &&
                     std::abs(from_keyframe.theta) <= settings_.keyframe_angle)) {
    return result;
  }
  add_keyframe(std::move(points));
  result.keyframe = true;
  return result;
}

// A match that moved too far is a divergence; one explaining far fewer of its points than the
// recent matches did is a wrong minimum (a turn taken for another, clutter in front).
void ScanMatcher::judge(MatchResult& result, const Pose2& increment, size_t points) {
  if (result.quality != MatchQuality::Ok) return;
  const double share = static_cast<double>(result.inliers) / static_cast<double>(std::max<size_t>(1, points));
  if (increment.distance() > settings_.max_jump) {
    result.quality = MatchQuality::Diverged;
  } else if (share < settings_.min_inlier_ratio * typical_inlier_share_) {
    result.quality = MatchQuality::Ambiguous;
  } else {
    const auto running = [](double mean, double value) { return mean == 0 ? value : 0.9 * mean + 0.1 * value; };
    typical_residual_ = running(typical_residual_, result.residual);
    typical_inlier_share_ = running(typical_inlier_share_, share);
  }
}

// Odometry that jumps (a wheel slipping, a glitch in its stamps) would start the match far
// off: a guess this unlike the last motion matched is dropped for the prediction.
std::optional<Pose2> ScanMatcher::plausible(const std::optional<Pose2>& guess) const {
  if (!guess) return guess;
  const Pose2 change = last_taken_.inverse() * *guess;
  if (change.distance() > settings_.guess_jump || std::abs(change.theta) > settings_.guess_turn) return std::nullopt;
  return guess;
}

// A wrong initial guess (odometry lagging, a turn reversing or speeding up) converges to a
// wrong minimum, which shows as a residual well above the recent ones. Then the previous
// increment, no motion and turns of up to +-30 degrees from the guess are tried too, and the
// alignment explaining most points wins.
MatchResult ScanMatcher::best_alignment(const std::vector<Eigen::Vector2d>& points,
                                        const std::optional<Pose2>& motion_guess) const {
  const Pose2 guess = motion_guess.value_or(last_increment_);
  const Prior prior{pose_ * guess, motion_guess ? settings_.guess_weight : settings_.prior_weight};
  MatchResult best = align_to(map_->reference(), points, pose_ * guess, prior);
  const bool converged = best.quality == MatchQuality::Ok &&
                         (typical_residual_ == 0 || best.residual < settings_.suspicious_residual * typical_residual_);
  if (converged) return best;
  std::vector<Pose2> motions = {last_increment_, Pose2{}};
  for (const double turn : {-30.0, -20.0, -10.0, 10.0, 20.0, 30.0})
    motions.push_back({guess.x, guess.y, Pose2::normalize(guess.theta + turn * kDegree)});
  // The same start gives the same match: without odometry the guess is the last increment,
  // after a failure that is no motion.
  const auto same = [](const Pose2& a, const Pose2& b) { return a.x == b.x && a.y == b.y && a.theta == b.theta; };
  for (size_t m = 0; m < motions.size(); ++m) {
    const Pose2& motion = motions[m];
    if (same(motion, guess) || std::any_of(motions.begin(), motions.begin() + static_cast<long>(m),
                                           [&](const Pose2& earlier) { return same(earlier, motion); }))
      continue;
    MatchResult result = align_to(map_->reference(), points, pose_ * motion, prior);
    const bool better =
        result.quality == MatchQuality::Ok && (best.quality != MatchQuality::Ok || result.inliers > best.inliers ||
                                               (result.inliers == best.inliers && result.residual < best.residual));
    if (better) best = result;
  }
  return best;
}

void ScanMatcher::add_keyframe(std::vector<Eigen::Vector2d> points) {
  map_->insert(Keyframe(pose_, std::move(points), settings_));
  keyframe_pose_ = pose_;
}

}  // namespace scanbus::scan_matcher

namespace scanbus::scan_matcher {

MatcherSettings matcher_settings_from_config(const Config& section) {
  MatcherSettings s;
  s.range_min = section.number("range_min", s.range_min, 0, 1000);
  s.range_max = section.number("range_max", s.range_max, 0, 1000);
  s.opening = section.number("opening", s.opening / kDegree, 1, 360) * kDegree;
  s.max_correspondence = section.number("max_correspondence", s.max_correspondence, 0.001, 100);
  s.max_segment_gap = section.number("max_segment_gap", s.max_segment_gap, 0.001, 100);
  s.line_neighbours = static_cast<int>(section.integer("line_neighbours", s.line_neighbours, 1, 50));
  s.min_line_length = section.number("min_line_length", s.min_line_length, 0, 100);
  s.trim = section.number("trim", s.trim, 0.1, 1);
  s.max_iterations = static_cast<int>(section.integer("max_iterations", s.max_iterations, 1, 1000));
  s.epsilon = section.number("epsilon", s.epsilon, 0, 1);
  s.min_correspondences = static_cast<size_t>(section.integer("min_correspondences", 30, 3, 100000));
  s.max_jump = section.number("max_jump", s.max_jump, 0.001, 1000);
  s.keyframe_distance = section.number("keyframe_distance", s.keyframe_distance, 0, 1000);
  s.keyframe_angle = section.number("keyframe_angle", s.keyframe_angle / kDegree, 0, 180) * kDegree;
  s.inlier_distance = section.number("inlier_distance", s.inlier_distance, 0.001, 10);
  s.prior_weight = section.number("prior_weight", s.prior_weight, 0, 1e6);
  s.guess_weight = section.number("guess_weight", s.guess_weight, 0, 1e6);
  s.constant_velocity = section.flag("constant_velocity", s.constant_velocity);
  s.suspicious_residual = section.number("suspicious_residual", s.suspicious_residual, 1, 1000);
  s.map_keyframes = static_cast<int>(section.integer("map_keyframes", s.map_keyframes, 1, 100000));
  s.guess_jump = section.number("guess_jump", s.guess_jump, 0, 1000);
  s.guess_turn = section.number("guess_turn", s.guess_turn / kDegree, 0, 360) * kDegree;
  s.robust_scale = section.number("robust_scale", s.robust_scale, 0, 10);
  s.map_resolution = section.number("map_resolution", s.map_resolution, 0, 10);
  if (s.map_resolution > 0 && s.map_resolution < 0.001)
    section.fail("map_resolution", "must be 0 (every point) or at least 0.001 m");
  s.lost_after = static_cast<int>(section.integer("lost_after", s.lost_after, 1, 100000));
  s.min_inlier_ratio = section.number("min_inlier_ratio", s.min_inlier_ratio, 0, 1);
  if (s.range_max <= s.range_min) section.fail("range_max", "must be larger than range_min");
  return s;
}

}  // namespace scanbus::scan_matcher
