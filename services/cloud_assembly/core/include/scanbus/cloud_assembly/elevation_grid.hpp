// The ground cloud as a surveyor's elevation grid: square cells over the map's x-y plane,
// each with the mean height of the points that fell in it, their spread and their count
// (PDAL's writers.gdal "mean", "stdev" and "count"). What the laser saw on top is the
// surface: a box's top is its cells' height (a surface model, not bare earth).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace scanbus::cloud_assembly {

struct ElevationGridSettings {
  double cell_size = 0.5;       // m; the MAV paper's scan lines are a few centimetres apart along the
                                // flight, so half a metre holds dozens of returns at 30 Hz and 1 m/s
  size_t min_points = 3;        // fewer returns in a cell leave it empty (no height, not a guess)
  size_t max_cells = 20000000;  // the grid's budget (about 0.6 GB while gridding; 10 x 10 km at 2 m,
                                // 2 x 2 km at 0.5 m): a wider cloud is refused
};

// Row-major in raster order: row 0 is the northernmost (largest y), column 0 the westernmost
// (smallest x), as GeoTIFF and images store them. Empty cells hold NaN and count 0.
struct ElevationGrid {
  double cell_size = 0;
  double west = 0, north = 0;  // m: the map-frame x of column 0's west edge, y of row 0's north edge
  size_t columns = 0, rows = 0;
  std::vector<float> height;    // m, map frame
  std::vector<float> stdev;     // m: the spread of the cell's point heights (not the mean's uncertainty)
  std::vector<uint32_t> count;  // points in the cell

  size_t index(size_t row, size_t column) const { return row * columns + column; }
  // The cell's centre in the map frame.
  Eigen::Vector2d centre(size_t row, size_t column) const;
  size_t filled() const;

  struct Cell {
    Eigen::Vector3f top;  // the cell's centre at its mean height, map frame
    float stdev;          // m, as above
  };
  // The cells with a height, in raster order.
  std::vector<Cell> filled_cells() const;
};

struct ElevationGridError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws ElevationGridError naming the problem: no finite point, a cell size that is not
// positive, or an extent that needs more cells than the budget. Non-finite points are skipped.
ElevationGrid grid_elevation(const std::vector<Eigen::Vector3f>& points, const ElevationGridSettings& settings);

}  // namespace scanbus::cloud_assembly
