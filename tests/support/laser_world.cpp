#include "laser_world.hpp"

#include <cmath>
#include <limits>

namespace scanbus::test_support {

sensor::LaserScan LaserWorld::scan(const scan_matcher::Pose2& pose, const LaserModel& laser,
                                   std::mt19937& random) const {
  std::normal_distribution<double> jitter(0, laser.noise);
  sensor::LaserScan scan;
  scan.angle_min = laser.angle_min;
  scan.angle_increment = laser.angle_increment;
  const Eigen::Vector2d origin(pose.x, pose.y);
  for (int i = 0; i < laser.rays; ++i) {
    const double angle = pose.theta + laser.angle_min + i * laser.angle_increment;
    const Eigen::Vector2d ray(std::cos(angle), std::sin(angle));
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : segments_) {
      const Eigen::Vector2d edge = b - a, to_a = a - origin;
      const double d = ray.x() * edge.y() - ray.y() * edge.x();
      if (std::abs(d) < 1e-12) continue;
      const double t = (to_a.x() * edge.y() - to_a.y() * edge.x()) / d;
      const double s = (to_a.x() * ray.y() - to_a.y() * ray.x()) / d;
      if (t > 0 && s >= 0 && s <= 1) nearest = std::min(nearest, t);
    }
    const double range = nearest > laser.range_max ? std::numeric_limits<double>::infinity() : nearest + jitter(random);
    scan.ranges.push_back(static_cast<float>(range));
  }
  return scan;
}

std::vector<LaserWorld::Segment> LaserWorld::polyline(const std::vector<Eigen::Vector2d>& corners, bool closed) {
  std::vector<Segment> segments;
  for (size_t i = 0; i + 1 < corners.size(); ++i) segments.emplace_back(corners[i], corners[i + 1]);
  if (closed && corners.size() > 2) segments.emplace_back(corners.back(), corners.front());
  return segments;
}

LaserWorld LaserWorld::room() {
  auto segments = polyline({{-3, -2}, {4, -2}, {4, 3}, {-3, 3}}, true);
  const auto pillar = polyline({{1, 0.5}, {1.6, 0.5}, {1.6, 1.2}, {1, 1.2}}, true);
  segments.insert(segments.end(), pillar.begin(), pillar.end());
  return LaserWorld(segments);
}

LaserWorld LaserWorld::corridor() {
  // Each wall runs along x with 1 m wide, 0.3 m deep door recesses every 2 m (staggered
  // between the walls) and the far end closed: the texture that makes motion along a real
  // corridor observable. A bare corridor leaves it unconstrained (see the flat-ground test).
  std::vector<Eigen::Vector2d> left, right;
  for (double x = -5; x < 25; x += 2) {
    left.insert(left.end(), {{x, 1}, {x + 1, 1}, {x + 1, 1.3}, {x + 2, 1.3}});
    right.insert(right.end(), {{x, -1.3}, {x + 1, -1.3}, {x + 1, -1}, {x + 2, -1}});
  }
  left.emplace_back(25, 1);  // the far end
  right.emplace_back(25, -1);
  left.insert(left.end(), right.rbegin(), right.rend());
  auto segments = polyline(left, false);
  return LaserWorld(segments);
}

LaserWorld LaserWorld::flat_ground() { return LaserWorld(polyline({{-20, 0}, {60, 0}}, false)); }

LaserWorld LaserWorld::stepped_ground() {
  std::vector<Eigen::Vector2d> profile;
  for (int step = 0; step < 54; ++step) {
    const double x = -20 + 1.5 * step, y = step % 2 == 0 ? 0.0 : 0.3;
    profile.insert(profile.end(), {{x, y}, {x + 1.5, y}});
  }
  return LaserWorld(polyline(profile, false));
}

}  // namespace scanbus::test_support
