#include "scanbus/pose_estimation/laser_height.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>

namespace scanbus::pose_estimation {

double height_change(double dx, double dy, const Eigen::Quaterniond& attitude_before,
                     const Eigen::Quaterniond& attitude_after, const Eigen::Isometry3d& laser_in_body) {
  const Eigen::Vector3d laser_moved = attitude_before * (laser_in_body.linear() * Eigen::Vector3d(dx, dy, 0));
  // The laser sits off the body's centre: turning moves it without moving the body.
  const Eigen::Vector3d lever_turned = (attitude_after * laser_in_body.translation()) -
                                       (attitude_before * laser_in_body.translation());
  return (laser_moved - lever_turned).z();
}

namespace {

// The candidate line through a and b, its normal pointing away from the laser.
std::optional<GroundLine> line_through(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d along = b - a;
  if (along.norm() < 1e-6) return std::nullopt;
  GroundLine line;
  line.normal = Eigen::Vector2d(-along.y(), along.x()).normalized();
  line.distance = line.normal.dot(a);
  if (line.distance < 0) {
    line.normal = -line.normal;
    line.distance = -line.distance;
  }
  return line;
}

std::vector<size_t> inliers_of(const GroundLine& line, const std::vector<Eigen::Vector2d>& points, double distance) {
  std::vector<size_t> inliers;
  for (size_t i = 0; i < points.size(); ++i)
    if (std::abs(line.normal.dot(points[i]) - line.distance) <= distance) inliers.push_back(i);
  return inliers;
}

// Total least squares: the line through the inliers' centroid along their main direction.
GroundLine refit(const std::vector<Eigen::Vector2d>& points, const std::vector<size_t>& inliers) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (size_t i : inliers) centroid += points[i];
  centroid /= static_cast<double>(inliers.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (size_t i : inliers) scatter += (points[i] - centroid) * (points[i] - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  GroundLine line;
  line.normal = solver.eigenvectors().col(0);  // the smallest spread is across the line
  line.distance = line.normal.dot(centroid);
  if (line.distance < 0) {
    line.normal = -line.normal;
    line.distance = -line.distance;
  }
  line.inliers = inliers.size();
  return line;
}

}  // namespace

std::optional<GroundLine> fit_ground_line(const std::vector<Eigen::Vector2d>& points,
                                          const GroundLineSettings& settings) {
  const size_t n = points.size();
  if (n < std::max<size_t>(settings.min_points, 2)) return std::nullopt;
  constexpr size_t kCandidates = 32;
  const size_t half = n / 2;
  std::vector<size_t> best;
  for (size_t k = 0; k < kCandidates; ++k) {
    const size_t first = k * (n - half) / kCandidates;
    const auto line = line_through(points[first], points[first + half - 1]);
    if (!line) continue;
    auto inliers = inliers_of(*line, points, settings.inlier_distance);
    if (inliers.size() > best.size()) best = std::move(inliers);
  }
  const auto enough = [&](size_t count) {
    return count >= settings.min_points && static_cast<double>(count) >= settings.min_inlier_share * static_cast<double>(n);
  };
  if (!enough(best.size())) return std::nullopt;
  // Refit twice: the first fit's inliers may still miss points a candidate line cut close to.
  GroundLine line = refit(points, best);
  const auto inliers = inliers_of(line, points, settings.inlier_distance);
  if (!enough(inliers.size())) return std::nullopt;
  return refit(points, inliers);
}

std::optional<double> ground_clearance(const GroundLine& line, const Eigen::Quaterniond& attitude,
                                       const Eigen::Isometry3d& laser_in_body, double max_slope) {
  const Eigen::Matrix3d laser_in_map = attitude.toRotationMatrix() * laser_in_body.linear();
  const Eigen::Vector3d along = laser_in_map * Eigen::Vector3d(-line.normal.y(), line.normal.x(), 0);
  if (std::abs(along.z()) > std::sin(max_slope)) return std::nullopt;
  // From the laser, `distance` along `normal` (in the scan plane) reaches the ground.
  const Eigen::Vector3d towards_ground = laser_in_map * Eigen::Vector3d(line.normal.x(), line.normal.y(), 0);
  const double laser_clearance = -line.distance * towards_ground.z();
  return laser_clearance - (attitude * laser_in_body.translation()).z();
}

}  // namespace scanbus::pose_estimation
