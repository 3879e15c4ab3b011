#include "scanbus/room_measurement/histogram_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scanbus::room_measurement {

std::vector<Eigen::Vector3f> histogram_filter(const std::vector<Eigen::Vector3f>& points,
                                              const HistogramFilterSettings& settings) {
  std::vector<Eigen::Vector3f> near_removed;
  near_removed.reserve(points.size());
  const float min_range_squared = static_cast<float>(settings.min_range * settings.min_range);
  for (const auto& point : points)
    if (point.squaredNorm() >= min_range_squared) near_removed.push_back(point);
  if (near_removed.empty()) return near_removed;

  Eigen::Vector2f low = near_removed.front().head<2>(), high = low;
  for (const auto& point : near_removed) {
    low = low.cwiseMin(point.head<2>());
    high = high.cwiseMax(point.head<2>());
  }
  const int bins = settings.bins;
  const Eigen::Vector2f size = ((high - low) / static_cast<float>(bins)).cwiseMax(1e-6f);
  auto bin_of = [&](const Eigen::Vector3f& point) {
    const int ix = std::min(bins - 1, static_cast<int>((point.x() - low.x()) / size.x()));
    const int iy = std::min(bins - 1, static_cast<int>((point.y() - low.y()) / size.y()));
    return iy * bins + ix;
  };
  struct Bin {
    int count = 0;
    float z_min = std::numeric_limits<float>::max();
    float z_max = std::numeric_limits<float>::lowest();
  };
  std::vector<Bin> grid(static_cast<size_t>(bins) * bins);
  for (const auto& point : near_removed) {
    Bin& bin = grid[bin_of(point)];
    ++bin.count;
    bin.z_min = std::min(bin.z_min, point.z());
    bin.z_max = std::max(bin.z_max, point.z());
  }
  std::vector<Eigen::Vector3f> kept;
  const double reference_squared = settings.reference_range * settings.reference_range;
  for (const auto& point : near_removed) {
    const Bin& bin = grid[bin_of(point)];
    const double thinning = std::min(1.0, reference_squared / point.head<2>().cast<double>().squaredNorm());
    const double needed = std::max(3.0, settings.min_points * thinning);
    if (bin.count >= needed && bin.z_max - bin.z_min > settings.min_z_spread) kept.push_back(point);
  }
  return kept;
}

}  // namespace scanbus::room_measurement
