#include <gtest/gtest.h>

#include <cmath>

#include "scanbus/transforms/transform_buffer.hpp"

using namespace scanbus::transforms;

namespace {

Eigen::Isometry3d pose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translate(Eigen::Vector3d(x, y, z));
  t.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return t;
}

}  // namespace

TEST(TransformSeries, InterpolatesTranslationAndRotation) {
  TransformSeries series;
  series.add(10.0, pose(0, 0, 1, 0));
  series.add(11.0, pose(2, 0, 3, M_PI / 2));
  const Eigen::Isometry3d middle = series.at(10.25);
  EXPECT_NEAR(middle.translation().x(), 0.5, 1e-12);
  EXPECT_NEAR(middle.translation().z(), 1.5, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(middle.linear()).angle(), M_PI / 8, 1e-9);
  EXPECT_NEAR(series.at(11.0).translation().x(), 2, 1e-12);
}

TEST(TransformSeries, ExtrapolationBeyondTheBoundIsAnError) {
  TransformSeries series;
  EXPECT_THROW(series.at(0), TransformError);
  series.add(10.0, pose(0, 0, 0, 0));
  series.add(11.0, pose(1, 0, 0, 0));
  EXPECT_NEAR(series.at(11.05, 0.1).translation().x(), 1, 1e-12);  // held within the bound
  try {
    series.at(11.5, 0.1);
    FAIL();
  } catch (const TransformError& e) {
    EXPECT_NE(std::string(e.what()).find("0.500 s after the newest"), std::string::npos) << e.what();
  }
  EXPECT_THROW(series.at(9.0), TransformError);
}

TEST(TransformSeries, AGapWiderThanTheBoundIsNotBridged) {
  TransformSeries series;
  series.add(10.0, pose(0, 0, 0, 0));
  series.add(10.1, pose(0.1, 0, 0, 0));
  series.add(12.1, pose(5, 0, 0, 0));  // the source restarted
  EXPECT_NEAR(series.at(10.05, 0, 1.0).translation().x(), 0.05, 1e-12);
  EXPECT_NEAR(series.at(12.1, 0, 1.0).translation().x(), 5, 1e-12);  // on a sample: no gap to bridge
  EXPECT_THROW(series.at(11.0, 0, 1.0), TransformGap);
  EXPECT_NEAR(series.at(11.0).translation().x(), 2.305, 1e-12);  // unbounded, as tf2
  TransformBuffer buffer;
  buffer.limit_gap("base_link", 1.0);
  buffer.add("map", "odom", 10.0, pose(0, 0, 0, 0));  // a slow map -> odom: not limited
  buffer.add("map", "odom", 12.1, pose(0, 0, 0, 0));
  buffer.add("odom", "base_link", 10.0, pose(0, 0, 0, 0));
  buffer.add("odom", "base_link", 12.1, pose(5, 0, 0, 0));
  EXPECT_NEAR(buffer.lookup("map", "odom", 11.0).translation().x(), 0, 1e-12);
  try {
    buffer.lookup("map", "base_link", 11.0);
    FAIL();
  } catch (const TransformGap& e) {
    EXPECT_NE(std::string(e.what()).find("'odom' -> 'base_link': stamp 11.000 falls in a gap of 2.100 s"),
              std::string::npos)
        << e.what();
  }
}

TEST(TransformSeries, OutOfOrderSamplesFindTheirPlaceAndOldOnesAreDropped) {
  TransformSeries series(2.0);
  series.add(1.0, pose(1, 0, 0, 0));
  series.add(3.0, pose(3, 0, 0, 0));
  series.add(2.0, pose(2, 0, 0, 0));
  EXPECT_NEAR(series.at(2.5).translation().x(), 2.5, 1e-12);
  series.add(4.0, pose(4, 0, 0, 0));  // 1.0 is now more than 2 s behind
  EXPECT_EQ(series.size(), 3u);
  EXPECT_DOUBLE_EQ(series.oldest(), 2.0);
}

TEST(TransformBuffer, ChainsStaticAndTimedTransforms) {
  TransformBuffer buffer;
  // The MAV paper's chain: laser on base_link (static), base_link in the map (moving).
  Eigen::Isometry3d laser = Eigen::Isometry3d::Identity();
  laser.translate(Eigen::Vector3d(0, 0, -0.1));
  laser.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  buffer.set_static("base_link", "laser", laser);
  buffer.add("map", "base_link", 0.0, pose(0, 0, 3, 0));
  buffer.add("map", "base_link", 1.0, pose(1, 0, 3, 0));
  // A return 2.9 m along the laser's x (straight down) lies on the ground under the body.
  const Eigen::Vector3d ground = buffer.lookup("map", "laser", 0.5) * Eigen::Vector3d(2.9, 0, 0);
  EXPECT_NEAR(ground.x(), 0.5, 1e-9);
  EXPECT_NEAR(ground.z(), 0.0, 1e-9);
  // And back: the inverse chain.
  const Eigen::Vector3d in_laser = buffer.lookup("laser", "map", 0.5) * ground;
  EXPECT_NEAR(in_laser.x(), 2.9, 1e-9);
  EXPECT_NEAR((buffer.lookup("base_link", "base_link", 7.0).matrix() - Eigen::Matrix4d::Identity()).norm(), 0, 1e-12);
}

TEST(TransformBuffer, ErrorsNameTheFrameAndTheTime) {
  TransformBuffer buffer(10.0, 0.05);
  buffer.add("map", "base_link", 0.0, pose(0, 0, 0, 0));
  buffer.add("map", "base_link", 1.0, pose(1, 0, 0, 0));
  std::string why;
  EXPECT_FALSE(buffer.try_lookup("map", "laser", 0.5, &why));
  EXPECT_NE(why.find("not connected"), std::string::npos) << why;
  EXPECT_FALSE(buffer.connected("map", "laser"));
  buffer.set_static("base_link", "laser", Eigen::Isometry3d::Identity());
  EXPECT_TRUE(buffer.connected("map", "laser"));  // at any time, though not at every
  EXPECT_TRUE(buffer.try_lookup("map", "laser", 1.04));
  EXPECT_FALSE(buffer.try_lookup("map", "laser", 1.2, &why));
  EXPECT_NE(why.find("'map' -> 'base_link'"), std::string::npos) << why;
  EXPECT_NE(why.find("after the newest"), std::string::npos) << why;
  EXPECT_THROW(buffer.set_static("odom", "laser", Eigen::Isometry3d::Identity()), TransformError);
  EXPECT_THROW(buffer.add("map", "map", 0, Eigen::Isometry3d::Identity()), TransformError);
  buffer.set_static("laser", "a", Eigen::Isometry3d::Identity());
  EXPECT_THROW(buffer.set_static("a", "map", Eigen::Isometry3d::Identity()), TransformError) << "would close a cycle";
}
