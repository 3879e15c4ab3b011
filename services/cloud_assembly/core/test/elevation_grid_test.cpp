#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "scanbus/cloud_assembly/elevation_grid.hpp"

using namespace scanbus::cloud_assembly;

namespace {

// A sloped plane sampled on a fine lattice with noise of a known spread.
std::vector<Eigen::Vector3f> sloped_cloud(double noise, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> error(0, noise);
  std::vector<Eigen::Vector3f> points;
  for (double x = -3.99; x < 4; x += 0.02)
    for (double y = -1.99; y < 2; y += 0.02) points.emplace_back(x, y, 0.1 * x - 0.05 * y + 2 + error(random));
  return points;
}

}  // namespace

TEST(ElevationGrid, CellsHoldTheMeanHeightAndSpreadOfTheirPoints) {
  const auto grid = grid_elevation(sloped_cloud(0.02, 1), {0.5, 3});
  ASSERT_EQ(grid.columns, 16u);  // -4 .. 4 m
  ASSERT_EQ(grid.rows, 8u);      // 2 .. -2 m, row 0 north
  EXPECT_DOUBLE_EQ(grid.west, -4.0);
  EXPECT_DOUBLE_EQ(grid.north, 2.0);
  EXPECT_EQ(grid.filled(), 128u);
  double worst_height = 0, worst_spread = 0;
  for (size_t row = 0; row < grid.rows; ++row)
    for (size_t column = 0; column < grid.columns; ++column) {
      const size_t i = grid.index(row, column);
      const Eigen::Vector2d c = grid.centre(row, column);
      worst_height = std::max(worst_height, std::abs(grid.height[i] - (0.1 * c.x() - 0.05 * c.y() + 2)));
      // The slope across a cell adds sqrt(0.1^2 + 0.05^2) * 0.5 / sqrt(12) = 0.016 m to the noise's 0.02.
      worst_spread = std::max(worst_spread, std::abs(grid.stdev[i] - std::hypot(0.02, 0.0161)));
      EXPECT_EQ(grid.count[i], 625u);
    }
  EXPECT_LT(worst_height, 0.005);  // 625 points: the mean is within 4 sigma of 0.8 mm
  EXPECT_LT(worst_spread, 0.003);
}

TEST(ElevationGrid, SparseCellsAndNonFinitePointsAreLeftOut) {
  std::vector<Eigen::Vector3f> points = {{0.1f, 0.1f, 1}, {0.2f, 0.2f, 3},    {0.3f, 0.3f, 2},  // cell (0, 0)
                                         {1.1f, 0.1f, 5},                                       // alone in its cell
                                         {NAN, 0.0f, 9},  {0.0f, INFINITY, 9}};
  const auto grid = grid_elevation(points, {1.0, 3});
  ASSERT_EQ(grid.columns, 2u);
  ASSERT_EQ(grid.rows, 1u);
  EXPECT_FLOAT_EQ(grid.height[0], 2.0f);
  EXPECT_NEAR(grid.stdev[0], std::sqrt(2.0 / 3.0), 1e-6);
  EXPECT_TRUE(std::isnan(grid.height[1]));
  EXPECT_EQ(grid.count[1], 0u);
  EXPECT_EQ(grid.filled(), 1u);
  const auto cells = grid.filled_cells();  // only the cell with a height, at its centre
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_TRUE(cells[0].top.isApprox(Eigen::Vector3f(0.5f, 0.5f, 2.0f))) << cells[0].top.transpose();
  EXPECT_FLOAT_EQ(cells[0].stdev, grid.stdev[0]);
}

TEST(ElevationGrid, BadInputIsRefusedWithTheReason) {
  const std::vector<Eigen::Vector3f> wide = {{0, 0, 0}, {50000, 50000, 0}};
  try {
    grid_elevation(wide, {0.5, 1});
    FAIL() << "a 50 km cloud at 0.5 m fits no budget";
  } catch (const ElevationGridError& e) {
    EXPECT_NE(std::string(e.what()).find("budget"), std::string::npos) << e.what();
  }
  EXPECT_THROW(grid_elevation(wide, {0.0, 1}), ElevationGridError);
  EXPECT_THROW(grid_elevation({{NAN, 0, 0}}, {0.5, 1}), ElevationGridError);
}
