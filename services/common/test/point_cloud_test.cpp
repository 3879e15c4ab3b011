#include <gtest/gtest.h>

#include "scanbus/point_cloud.hpp"

using namespace scanbus;

TEST(PointCloud, RoundTrip) {
  const std::vector<CloudPoint> points = {{{1.f, 2.f, 3.f}, 4.f}, {{-1.f, 0.5f, 7.f}, 0.f}};
  const auto cloud = to_point_cloud2(points, "scanner", {});
  EXPECT_EQ(cloud.width(), 2u);
  EXPECT_EQ(cloud.row_step(), 32u);
  const auto back = from_point_cloud2(cloud);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].position, points[1].position);
  EXPECT_EQ(back[0].intensity, 4.f);
}

TEST(PointCloud, RejectsTruncatedData) {
  auto cloud = to_point_cloud2({{{1.f, 2.f, 3.f}, 4.f}}, "scanner", {});
  cloud.data().resize(10);
  EXPECT_THROW(from_point_cloud2(cloud), std::invalid_argument);
}

TEST(PointCloud, RejectsMissingField) {
  auto cloud = to_point_cloud2({{{1.f, 2.f, 3.f}, 4.f}}, "scanner", {});
  cloud.fields()[2].name("w");
  EXPECT_THROW(from_point_cloud2(cloud), std::invalid_argument);
}
