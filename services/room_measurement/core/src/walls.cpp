#include "scanbus/room_measurement/walls.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace scanbus::room_measurement {

namespace {

double percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0;
  const size_t index = std::min(values.size() - 1, static_cast<size_t>(fraction * (values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(index), values.end());
  return values[index];
}

// Share of `slot`-wide slots between low and high that hold at least one value.
double coverage(const std::vector<double>& values, double low, double high, double slot) {
  const int slots = std::max(1, static_cast<int>(std::ceil((high - low) / slot)));
  std::vector<bool> occupied(static_cast<size_t>(slots), false);
  for (double v : values)
    if (v >= low && v <= high) occupied[std::min(slots - 1, static_cast<int>((v - low) / slot))] = true;
  return static_cast<double>(std::count(occupied.begin(), occupied.end(), true)) / slots;
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

bool segments_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, const Eigen::Vector2d& d) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a), d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}

// Two neighbours in the turn that are parallel cannot meet in a corner. When one stands
// nearer the scanner it is an object in front of the other (a tall wardrobe hides the
// wall behind it from the filter): drop it, so the wall behind meets its true neighbours.
void drop_occluders(const std::vector<WallLine>& walls, double min_sine, std::vector<size_t>& order) {
  bool changed = true;
  while (changed && order.size() >= 3) {
    changed = false;
    for (size_t i = 0; i < order.size() && !changed; ++i) {
      const size_t next = (i + 1) % order.size();
      const WallLine& a = walls[order[i]];
      const WallLine& b = walls[order[next]];
      if (std::abs(cross(a.normal, b.normal)) >= min_sine || a.normal.dot(b.normal) < 0) continue;
      order.erase(order.begin() + static_cast<long>(a.offset < b.offset ? i : next));
      changed = true;
    }
    // Dropping one may leave the same wall on both sides of the gap.
    for (size_t i = 0; i + 1 < order.size();) {
      if (order[i] == order[i + 1]) {
        order.erase(order.begin() + static_cast<long>(i) + 1);
      } else {
        ++i;
      }
    }
    if (order.size() > 1 && order.front() == order.back()) order.pop_back();
  }
}

}  // namespace

WallLine fit_wall(std::vector<Eigen::Vector3f> inliers) {
  WallLine wall;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : inliers) mean += p.head<2>().cast<double>();
  mean /= static_cast<double>(inliers.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : inliers) {
    const Eigen::Vector2d q = p.head<2>().cast<double>() - mean;
    scatter += q * q.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  wall.normal = solver.eigenvectors().col(0);  // smallest eigenvalue first
  wall.offset = wall.normal.dot(mean);
  if (wall.offset < 0) {  // face the scanner: the normal points from the origin to the wall
    wall.normal = -wall.normal;
    wall.offset = -wall.offset;
  }
  const auto n = static_cast<double>(inliers.size());
  wall.rms = std::sqrt(std::max(0.0, solver.eigenvalues()(0)) / n);
  wall.offset_sigma = wall.rms / std::sqrt(n);
  std::vector<double> along, heights;
  for (const auto& p : inliers) {
    along.push_back(wall.direction().dot(p.head<2>().cast<double>()));
    heights.push_back(p.z());
  }
  wall.start = percentile(along, 0.01);
  wall.end = percentile(along, 0.99);
  wall.z_low = percentile(heights, 0.02);
  wall.z_high = percentile(heights, 0.98);
  wall.z_coverage = coverage(heights, wall.z_low, wall.z_high, 0.1);
  wall.length_coverage = coverage(along, wall.start, wall.end, 0.1);
  wall.inliers = std::move(inliers);
  return wall;
}

std::vector<WallLine> merge_collinear(std::vector<WallLine> walls, double angle, double same, double tail) {
  std::sort(walls.begin(), walls.end(), [](const auto& a, const auto& b) { return a.inliers.size() > b.inliers.size(); });
  for (size_t i = 0; i < walls.size(); ++i) {
    for (size_t j = i + 1; j < walls.size();) {
      const double gap = std::abs(walls[i].offset - walls[j].offset);
      const bool parallel = walls[i].normal.dot(walls[j].normal) > std::cos(angle);
      if (parallel && gap < same) {
        auto points = walls[i].inliers;
        points.insert(points.end(), walls[j].inliers.begin(), walls[j].inliers.end());
        walls[i] = fit_wall(std::move(points));
        walls.erase(walls.begin() + static_cast<long>(j));
        j = i + 1;
      } else if (parallel && gap < tail) {
        walls.erase(walls.begin() + static_cast<long>(j));
      } else {
        ++j;
      }
    }
  }
  return walls;
}

std::optional<Polygon> room_polygon(const std::vector<WallLine>& walls, const PolygonSettings& settings,
                                    std::string& why) {
  // The farthest wall in each direction, a quarter of a degree at a time.
  constexpr int kSteps = 1440;
  std::vector<int> seen(kSteps, -1);
  for (int step = 0; step < kSteps; ++step) {
    const double angle = 2 * M_PI * step / kSteps;
    const Eigen::Vector2d ray(std::cos(angle), std::sin(angle));
    double farthest = 0;
    for (size_t w = 0; w < walls.size(); ++w) {
      const double facing = walls[w].normal.dot(ray);
      if (facing < 1e-6) continue;
      const double t = walls[w].offset / facing;
      const double along = walls[w].direction().dot(t * ray);
      if (along < walls[w].start - settings.extent_tolerance || along > walls[w].end + settings.extent_tolerance) continue;
      if (t > farthest) {
        farthest = t;
        seen[step] = static_cast<int>(w);
      }
    }
  }
  // Runs of one wall around the turn; short runs are clutter.
  std::vector<std::pair<int, int>> runs;  // wall, length in steps
  for (int step = 0; step < kSteps; ++step) {
    if (!runs.empty() && runs.back().first == seen[step]) {
      ++runs.back().second;
    } else {
      runs.push_back({seen[step], 1});
    }
  }
  if (runs.size() > 1 && runs.front().first == runs.back().first) {
    runs.front().second += runs.back().second;
    runs.pop_back();
  }
  const int min_steps = static_cast<int>(settings.min_run_deg / 360.0 * kSteps);
  const int max_gap_steps = static_cast<int>(settings.max_gap_deg / 360.0 * kSteps);
  Polygon polygon;
  for (const auto& [wall, length] : runs) {
    if (wall < 0) {  // corners and occlusions leave short gaps; corners come from intersections
      if (length > max_gap_steps) {
        why = "no wall seen over " + std::to_string(length / 4) + " degrees: the walls do not close a room";
        return std::nullopt;
      }
      continue;
    }
    if (length < min_steps) continue;
    if (!polygon.walls.empty() && polygon.walls.back() == static_cast<size_t>(wall)) continue;
    polygon.walls.push_back(static_cast<size_t>(wall));
  }
  if (polygon.walls.size() > 1 && polygon.walls.front() == polygon.walls.back()) polygon.walls.pop_back();
  drop_occluders(walls, std::sin(settings.min_wall_angle_deg * M_PI / 180), polygon.walls);
  if (polygon.walls.size() < 3) {
    why = "only " + std::to_string(polygon.walls.size()) + " walls around the scanner: not a room";
    return std::nullopt;
  }

  // Corners: each wall meets the next; neighbours must not be (nearly) parallel.
  Eigen::Vector2d low(1e9, 1e9), high(-1e9, -1e9);
  for (size_t w : polygon.walls)
    for (const auto& p : walls[w].inliers) {
      low = low.cwiseMin(p.head<2>().cast<double>());
      high = high.cwiseMax(p.head<2>().cast<double>());
    }
  const size_t count = polygon.walls.size();
  for (size_t i = 0; i < count; ++i) {
    const WallLine& a = walls[polygon.walls[(i + count - 1) % count]];
    const WallLine& b = walls[polygon.walls[i]];
    const double sine = std::abs(cross(a.normal, b.normal));
    if (sine < std::sin(settings.min_wall_angle_deg * M_PI / 180)) {
      why = "neighbouring walls " + std::to_string(i == 0 ? count : i) + " and " + std::to_string(i + 1) +
            " are parallel: a wall between them is missing, the walls do not close a room";
      return std::nullopt;
    }
    const Eigen::Vector2d corner = intersect_lines(a.normal, a.offset, b.normal, b.offset);
    if ((corner.array() < low.array() - settings.corner_margin).any() ||
        (corner.array() > high.array() + settings.corner_margin).any()) {
      why = "walls " + std::to_string(i == 0 ? count : i) + " and " + std::to_string(i + 1) +
            " meet outside the scanned area: the walls do not close a room";
      return std::nullopt;
    }
    polygon.corners.push_back(corner);
  }
  for (size_t i = 0; i < count; ++i)
    for (size_t j = i + 2; j < count; ++j) {
      if (i == 0 && j == count - 1) continue;  // neighbours share a corner
      if (segments_cross(polygon.corners[i], polygon.corners[(i + 1) % count], polygon.corners[j],
                         polygon.corners[(j + 1) % count])) {
        why = "the walls cross each other: not a simple room outline";
        return std::nullopt;
      }
    }
  return polygon;
}

Eigen::Vector2d intersect_lines(const Eigen::Vector2d& na, double oa, const Eigen::Vector2d& nb, double ob) {
  Eigen::Matrix2d lines;
  lines << na.transpose(), nb.transpose();
  return lines.inverse() * Eigen::Vector2d(oa, ob);
}

double polygon_area(const std::vector<Eigen::Vector2d>& corners) {
  double twice = 0;  // shoelace
  for (size_t i = 0; i < corners.size(); ++i) twice += cross(corners[i], corners[(i + 1) % corners.size()]);
  return std::abs(twice) / 2;
}

}  // namespace scanbus::room_measurement
