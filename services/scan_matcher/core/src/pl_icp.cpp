#include "scanbus/scan_matcher/pl_icp.hpp"

#include <Eigen/Dense>
#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>

namespace scanbus::scan_matcher {

namespace {

struct PointSet {
  std::vector<Eigen::Vector2d> points;
  size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(size_t index, size_t dim) const { return points[index][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointSet>, PointSet, 2>;

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

std::vector<LocalLine> local_lines(const std::vector<Eigen::Vector2d>& points, int neighbours, double max_gap) {
  std::vector<LocalLine> lines(points.size());
  const long count = static_cast<long>(points.size());
  for (long i = 0; i < count; ++i) {
    long low = i, high = i;
    while (low > 0 && i - low < neighbours && (points[low - 1] - points[low]).norm() <= max_gap) --low;
    while (high + 1 < count && high - i < neighbours && (points[high + 1] - points[high]).norm() <= max_gap) ++high;
    if (high - low < 1) continue;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (long j = low; j <= high; ++j) centre += points[j];
    centre /= static_cast<double>(high - low + 1);
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (long j = low; j <= high; ++j) scatter += (points[j] - centre) * (points[j] - centre).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
    // Not line-like (a corner, a pillar's edge): no trustworthy direction.
    if (solver.eigenvalues()(0) > kMaxLineSpread * solver.eigenvalues()(1)) continue;
    lines[i] = {true, centre, solver.eigenvectors().col(0)};
  }
  return lines;
}

}  // namespace

struct ScanMatcher::Reference {
  Reference(std::vector<Eigen::Vector2d> points, const MatcherSettings& settings)
      : set{std::move(points)}, lines(local_lines(set.points, settings.line_neighbours, settings.max_segment_gap)),
        tree(2, set, {10}) {
    tree.buildIndex();
  }
  PointSet set;
  std::vector<LocalLine> lines;
  KdTree tree;
};

ScanMatcher::ScanMatcher(MatcherSettings settings) : settings_(settings) {}
ScanMatcher::~ScanMatcher() = default;

std::vector<Eigen::Vector2d> ScanMatcher::points_of(const Scan& scan) const {
  std::vector<Eigen::Vector2d> points;
  const double middle = scan.angle_min + scan.angle_increment * (static_cast<double>(scan.ranges.size()) - 1) / 2;
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double range = scan.ranges[i];
    const double angle = scan.angle_min + scan.angle_increment * static_cast<double>(i);
    // NaN and inf fail these comparisons too.
    if (!(range >= settings_.range_min && range <= settings_.range_max)) continue;
    if (std::abs(Pose2::normalize(angle - middle)) > settings_.opening / 2) continue;
    points.emplace_back(range * std::cos(angle), range * std::sin(angle));
  }
  return points;
}

MatchResult ScanMatcher::align(const std::vector<Eigen::Vector2d>& reference, const std::vector<Eigen::Vector2d>& scan,
                               const Pose2& guess) const {
  const Reference built(reference, settings_);
  return align_to(built, scan, guess);
}

MatchResult ScanMatcher::align_to(const Reference& reference, const std::vector<Eigen::Vector2d>& scan,
                                  const Pose2& guess) const {
  MatchResult result;
  const auto& ref = reference.set.points;
  if (ref.size() < 2) {
    result.quality = MatchQuality::TooFewCorrespondences;
    return result;
  }
  Eigen::Vector3d x(guess.x, guess.y, guess.theta);
  std::vector<Correspondence> matches;
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
  const double max_distance_squared = settings_.max_correspondence * settings_.max_correspondence;
  for (result.iterations = 1; result.iterations <= settings_.max_iterations; ++result.iterations) {
    const Eigen::Rotation2Dd rotation(x[2]);
    matches.clear();
    for (size_t i = 0; i < scan.size(); ++i) {
      const Eigen::Vector2d q = rotation * scan[i] + x.head<2>();
      unsigned int found = 0;  // nanoflann 1.4's index type
      double distance_squared = 0;
      reference.tree.knnSearch(q.data(), 1, &found, &distance_squared);
      const size_t nearest = found;
      if (distance_squared > max_distance_squared) continue;
      const LocalLine& line = reference.lines[nearest];
      if (!line.valid) continue;
      matches.push_back({i, line.normal, line.normal.dot(q - line.centre)});
    }
    if (matches.size() < settings_.min_correspondences) {
      result.quality = MatchQuality::TooFewCorrespondences;
      break;
    }
    // Trimming: the worst matches are outliers (moved objects, new surfaces).
    const size_t keep = std::max(settings_.min_correspondences,
                                 static_cast<size_t>(settings_.trim * static_cast<double>(matches.size())));
    std::nth_element(matches.begin(), matches.begin() + static_cast<long>(keep - 1), matches.end(),
                     [](const auto& a, const auto& b) { return std::abs(a.error) < std::abs(b.error); });
    matches.resize(keep);
    // Gauss-Newton on e_i = n_i . (R(theta) q_i + t - p_i).
    hessian.setZero();
    Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
    double error_sum = 0;
    const double c = std::cos(x[2]), s = std::sin(x[2]);
    for (const auto& m : matches) {
      const Eigen::Vector2d& q = scan[m.point];
      const Eigen::Vector2d turned(-s * q.x() - c * q.y(), c * q.x() - s * q.y());  // dR/dtheta q
      const Eigen::Vector3d jacobian(m.normal.x(), m.normal.y(), m.normal.dot(turned));
      hessian += jacobian * jacobian.transpose();
      gradient += jacobian * m.error;
      error_sum += std::abs(m.error);
    }
    const Eigen::Vector3d step = hessian.ldlt().solve(-gradient);
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
    double squares = 0;
    for (const auto& m : matches) squares += m.error * m.error;
    const double variance = squares / std::max<double>(1.0, static_cast<double>(matches.size()) - 3);
    result.covariance = variance * hessian.inverse();
  }
  return result;
}

MatchResult ScanMatcher::add_scan(const Scan& scan, const std::optional<Pose2>& motion_guess) {
  std::vector<Eigen::Vector2d> points = points_of(scan);
  if (!keyframe_) {
    keyframe_ = std::make_unique<Reference>(std::move(points), settings_);
    keyframe_pose_ = pose_;
    MatchResult first;
    first.quality = MatchQuality::NoReference;
    first.pose = pose_;
    first.keyframe = true;
    return first;
  }
  const Pose2 motion = motion_guess.value_or(last_increment_);
  const Pose2 guess = keyframe_pose_.inverse() * (pose_ * motion);  // predicted pose in the keyframe's frame
  MatchResult result = align_to(*keyframe_, points, guess);
  const Pose2 previous = pose_;
  Pose2 matched = keyframe_pose_ * result.increment;
  if (result.quality == MatchQuality::Ok && (previous.inverse() * matched).distance() > settings_.max_jump)
    result.quality = MatchQuality::Diverged;
  if (result.quality == MatchQuality::Ok) {
    pose_ = matched;
  } else if (motion_guess) {
    pose_ = pose_ * *motion_guess;  // an external measurement, not a jump
  }
  result.increment = previous.inverse() * pose_;
  last_increment_ = result.quality == MatchQuality::Ok ? result.increment : Pose2{};
  result.pose = pose_;
  const Pose2 from_keyframe = keyframe_pose_.inverse() * pose_;
  if (result.quality == MatchQuality::Ok && (from_keyframe.distance() > settings_.keyframe_distance ||
                                             std::abs(from_keyframe.theta) > settings_.keyframe_angle)) {
    keyframe_ = std::make_unique<Reference>(std::move(points), settings_);
    keyframe_pose_ = pose_;
    result.keyframe = true;
  }
  return result;
}

}  // namespace scanbus::scan_matcher
