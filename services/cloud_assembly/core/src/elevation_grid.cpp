#include "scanbus/cloud_assembly/elevation_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace scanbus::cloud_assembly {

Eigen::Vector2d ElevationGrid::centre(size_t row, size_t column) const {
  return {west + (static_cast<double>(column) + 0.5) * cell_size, north - (static_cast<double>(row) + 0.5) * cell_size};
}

size_t ElevationGrid::filled() const {
  size_t cells = 0;
  for (uint32_t c : count) cells += c > 0;
  return cells;
}

std::vector<ElevationGrid::Cell> ElevationGrid::filled_cells() const {
  std::vector<Cell> cells;
  cells.reserve(filled());
  for (size_t row = 0; row < rows; ++row)
    for (size_t column = 0; column < columns; ++column) {
      const size_t i = index(row, column);
      if (count[i] == 0) continue;
      const Eigen::Vector2d at = centre(row, column);
      cells.push_back({Eigen::Vector3f(static_cast<float>(at.x()), static_cast<float>(at.y()), height[i]), stdev[i]});
    }
  return cells;
}

ElevationGrid grid_elevation(const std::vector<Eigen::Vector3f>& points, const ElevationGridSettings& settings) {
  if (!(settings.cell_size > 0) || !std::isfinite(settings.cell_size))
    throw ElevationGridError("cell size " + std::to_string(settings.cell_size) + " m: must be positive");
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const auto& p : points)
    if (p.allFinite()) low = low.cwiseMin(p.head<2>().cast<double>()), high = high.cwiseMax(p.head<2>().cast<double>());
  if (!low.allFinite()) throw ElevationGridError("no finite point to grid");
  ElevationGrid grid;
  grid.cell_size = settings.cell_size;
  // Cell edges on multiples of the cell size, so grids of two clouds line up.
  grid.west = std::floor(low.x() / settings.cell_size) * settings.cell_size;
  grid.north = (std::floor(high.y() / settings.cell_size) + 1) * settings.cell_size;
  const double columns = std::floor(high.x() / settings.cell_size) - std::floor(low.x() / settings.cell_size) + 1;
  const double rows = std::floor(high.y() / settings.cell_size) - std::floor(low.y() / settings.cell_size) + 1;
  if (columns * rows > static_cast<double>(settings.max_cells))
    throw ElevationGridError("the cloud spans " + std::to_string(high.x() - low.x()) + " x " +
                             std::to_string(high.y() - low.y()) + " m: " + std::to_string(columns * rows) +
                             " cells of " + std::to_string(settings.cell_size) + " m, more than the budget of " +
                             std::to_string(settings.max_cells));
  grid.columns = static_cast<size_t>(columns);
  grid.rows = static_cast<size_t>(rows);
  const size_t cells = grid.columns * grid.rows;
  // Welford's running mean and spread per cell: one pass, no cancellation over tall clouds.
  std::vector<double> mean(cells, 0.0), squares(cells, 0.0);
  grid.count.assign(cells, 0);
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    // Clamped: rounding may put a point on the extent's edge a hair outside it.
    const double column = std::clamp(std::floor((p.x() - grid.west) / settings.cell_size), 0.0, columns - 1);
    const double row = std::clamp(std::floor((grid.north - p.y()) / settings.cell_size), 0.0, rows - 1);
    const size_t i = grid.index(static_cast<size_t>(row), static_cast<size_t>(column));
    const double delta = p.z() - mean[i];
    mean[i] += delta / ++grid.count[i];
    squares[i] += delta * (p.z() - mean[i]);
  }
  grid.height.assign(cells, std::numeric_limits<float>::quiet_NaN());
  grid.stdev.assign(cells, std::numeric_limits<float>::quiet_NaN());
  for (size_t i = 0; i < cells; ++i) {
    if (grid.count[i] < std::max<size_t>(settings.min_points, 1)) {
      grid.count[i] = 0;
      continue;
    }
    grid.height[i] = static_cast<float>(mean[i]);
    grid.stdev[i] = static_cast<float>(std::sqrt(squares[i] / grid.count[i]));
  }
  return grid;
}

}  // namespace scanbus::cloud_assembly
