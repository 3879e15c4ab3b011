#include <gtest/gtest.h>

#include <cmath>

#include "scanbus/cloud_assembly/cloud_builder.hpp"

using namespace scanbus::cloud_assembly;

// The gate is sensor::kept_points' (its own tests); here the points come out in 3D at z = 0.
TEST(ScanPoints, AreTheKeptReturnsAtZeroHeight) {
  scanbus::sensor::LaserScan scan;
  scan.angle_min = -M_PI / 2;
  scan.angle_increment = M_PI / 2;  // -90, 0, +90 degrees
  scan.ranges = {2.0f, NAN, 40.0f};
  const auto points = scan_points(scan, {0, 30, 2 * M_PI});
  ASSERT_EQ(points.size(), 1u);
  EXPECT_NEAR(points[0].y(), -2.0, 1e-9);
  EXPECT_EQ(points[0].z(), 0.0);
}

TEST(ContinuousCloud, OnePointPerVoxelWithinTheBudget) {
  ContinuousCloud cloud(0.1, 3);
  cloud.add({{0.01, 0.01, 0.01}, {0.03, 0.05, 0.07}, {0.55, 0, 0}});
  EXPECT_EQ(cloud.size(), 2u);
  const auto points = cloud.points();
  bool mean_found = false;
  for (const auto& p : points) mean_found |= (p - Eigen::Vector3f(0.02f, 0.03f, 0.04f)).norm() < 1e-6;
  EXPECT_TRUE(mean_found);
  cloud.add({{-0.05, 0, 0}, {5, 5, 5}, {NAN, 0, 0}});  // a third voxel, then the budget is spent
  EXPECT_EQ(cloud.size(), 3u);
  EXPECT_EQ(cloud.dropped(), 2u);
  EXPECT_THROW(ContinuousCloud(0, 10), std::invalid_argument);
}

TEST(ScanWindow, AssemblesATimeSpanAndForgetsTheOldest) {
  ScanWindow window(2.0, 100);
  for (int k = 0; k < 40; ++k) window.add(k * 0.1, std::vector<Eigen::Vector3f>(2, Eigen::Vector3f::Constant(k)));
  EXPECT_EQ(window.scans(), 21u);  // 2 s behind the newest (3.9 s): 1.9 .. 3.9
  EXPECT_NEAR(window.oldest(), 1.9, 1e-9);
  EXPECT_EQ(window.assemble(2.0, 2.45).size(), 10u);  // scans 2.0 .. 2.4
  EXPECT_TRUE(window.assemble(5, 6).empty());
  ScanWindow small(100, 5);
  for (int k = 0; k < 4; ++k) small.add(k, std::vector<Eigen::Vector3f>(2, Eigen::Vector3f::Zero()));
  EXPECT_EQ(small.scans(), 2u);  // a point budget of 5 keeps two scans of two
}
