#include "scanbus/palette.hpp"

#include <gtest/gtest.h>

#include <set>

using namespace scanbus;

TEST(HeightColour, BlueLowGreenMiddleRedHigh) {
  EXPECT_EQ(height_colour(0, 0, 1), 0x0000FFu);
  EXPECT_EQ(height_colour(0.5, 0, 1), 0x00FF00u);
  EXPECT_EQ(height_colour(1, 0, 1), 0xFF0000u);
  EXPECT_EQ(height_colour(7, 0, 1), 0xFF0000u);
  EXPECT_EQ(height_colour(3, 2, 2), 0x00FF00u);  // no height span: the middle
}

TEST(WallColour, TenDistinctThenRepeating) {
  std::set<uint32_t> colours;
  for (size_t w = 0; w < 10; ++w) colours.insert(wall_colour(w));
  EXPECT_EQ(colours.size(), 10u);
  EXPECT_EQ(wall_colour(10), wall_colour(0));
}
