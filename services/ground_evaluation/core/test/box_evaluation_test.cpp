#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "scanbus/ground_evaluation/box_evaluation.hpp"

using namespace scanbus::ground_evaluation;

namespace {

// Ground from 1..7 x -1.5..1.5, 10,000 points a square metre drawn uniformly (about what
// fifteen passes of the MAV's laser leave), with boxes
// (length along their yaw) raising the points on their tops; 1 cm noise.
// `ground` under the scene (level by default) over `extent` (x from, x to, half width in y);
// a box's top is level, `size.z()` above the ground under its centre.
std::vector<Eigen::Vector3f> scene(
    const std::vector<std::pair<Eigen::Vector3d, double>>& boxes, const Eigen::Vector3d& size, double noise,
    const std::function<double(double, double)>& ground = [](double, double) { return 0.0; },
    const Eigen::Vector3d& extent = {1, 7, 1.5}) {
  std::mt19937 random(7);
  std::normal_distribution<double> gauss(0, noise);
  std::vector<Eigen::Vector3f> cloud;
  const auto inside = [&](double x, double y, const Eigen::Vector3d& centre, double yaw) {
    const Eigen::Vector2d local = Eigen::Rotation2Dd(-yaw) * Eigen::Vector2d(x - centre.x(), y - centre.y());
    return std::abs(local.x()) <= size.x() / 2 && std::abs(local.y()) <= size.y() / 2;
  };
  std::uniform_real_distribution<double> along(extent.x(), extent.y()), across(-extent.z(), extent.z());
  const int points = static_cast<int>(10000 * (extent.y() - extent.x()) * 2 * extent.z());
  for (int i = 0; i < points; ++i) {
    const double x = along(random), y = across(random);
    double z = ground(x, y);
    for (const auto& [centre, yaw] : boxes)
      if (inside(x, y, centre, yaw)) z = ground(centre.x(), centre.y()) + size.z();
    cloud.emplace_back(x + gauss(random), y + gauss(random), z + gauss(random));
  }
  return cloud;
}

}  // namespace

TEST(Footprint, RecoversARotatedRectangle) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> a(-0.3, 0.3), b(-0.2, 0.2);
  std::vector<Eigen::Vector2d> points;
  const double yaw = 0.3;
  for (int i = 0; i < 2000; ++i)
    points.push_back(Eigen::Rotation2Dd(yaw) * Eigen::Vector2d(a(random), b(random)) + Eigen::Vector2d(4, 1));
  const Footprint footprint = fit_footprint(points, 0.02);
  EXPECT_NEAR(footprint.length, 0.6, 0.005);
  EXPECT_NEAR(footprint.width, 0.4, 0.005);
  EXPECT_NEAR(footprint.yaw, yaw, 0.01);
  EXPECT_NEAR((footprint.centre - Eigen::Vector2d(4, 1)).norm(), 0, 0.005);
}

TEST(BoxEvaluation, TwoBoxesOnTheGroundGiveTheirRatio) {
  const Eigen::Vector3d size(0.6, 0.4, 0.3);
  const auto cloud = scene({{{4, -0.45, 0}, 0.0}, {{4, 0.45, 0}, 0.2}}, size, 0.01);
  const BoxEvaluation result = evaluate_boxes(cloud, 0.4, 0.6);
  ASSERT_TRUE(result.ok) << result.message;
  ASSERT_EQ(result.boxes.size(), 2u);
  for (const auto& box : result.boxes) {
    std::printf("box at (%.3f, %.3f): %.4f x %.4f x %.3f m, P %.2f %%\n", box.centre.x(), box.centre.y(), box.length,
                box.width, box.height, box.performance_percent);
    // About 2,400 points a box top with 1 cm noise: the sides to a few millimetres (the
    // orientation to about a degree is what limits them).
    EXPECT_NEAR(box.length, 0.6, 0.007);
    EXPECT_NEAR(box.width, 0.4, 0.007);
    EXPECT_NEAR(box.height, 0.3, 0.04);  // the highest point: noise adds to it
    EXPECT_GT(box.performance_percent, 98.0);
  }
  EXPECT_NEAR(result.ratio_actual, 0.4 / 0.6, 1e-12);
}

// On issue 19's development terrain (a 3 degree slope, a 0.4 m mound beside the boxes, a
// ditch and a step) the boxes stand out of the ground under them and are measured in their
// tops. (In a simulated flight's cloud over it, one plane through the whole ground found
// strips of the ground as "boxes"; this clean cloud does not show that.)
TEST(BoxEvaluation, BoxesOnASlopeWithAMoundAreFound) {
  const auto bump = [](double x, double y, double cx, double cy, double radius, double height) {
    const double r = std::hypot(x - cx, y - cy);
    return r < radius ? height * (1 + std::cos(M_PI * r / radius)) / 2 : 0.0;
  };
  const auto terrain = [&](double x, double y) {
    return 0.052 * x + bump(x, y, 6, 0.5, 3, 0.4) + bump(x, y, 2, -1, 1, -0.25) + (x > 8.5 ? 0.15 : 0.0);
  };
  const Eigen::Vector3d size(0.6, 0.4, 0.3);
  const auto cloud = scene({{{4, -0.45, 0}, 0.0}, {{4, 0.45, 0}, 0.0}}, size, 0.01, terrain, {-2, 11, 3});
  const BoxEvaluation result = evaluate_boxes(cloud, 0.4, 0.6);
  ASSERT_TRUE(result.ok) << result.message;
  for (const auto& box : result.boxes) {
    std::printf("box at (%.3f, %.3f): %.4f x %.4f m, P %.2f %%\n", box.centre.x(), box.centre.y(), box.length,
                box.width, box.performance_percent);
    EXPECT_NEAR(box.centre.x(), 4, 0.02);
    EXPECT_NEAR(std::abs(box.centre.y()), 0.45, 0.02);
    EXPECT_NEAR(box.length, 0.6, 0.01);
    EXPECT_NEAR(box.width, 0.4, 0.01);
  }
}

TEST(BoxEvaluation, WhatIsMissingIsSaid) {
  EXPECT_EQ(evaluate_boxes({}, 0.4, 0.6).message, "the cloud has 0 points, too few to find a ground");
  const auto flat = scene({}, {0.6, 0.4, 0.3}, 0.01);
  const BoxEvaluation none = evaluate_boxes(flat, 0.4, 0.6);
  EXPECT_FALSE(none.ok);
  EXPECT_EQ(none.message, "found 0 objects above the ground, expected 2 boxes");
  EXPECT_FALSE(evaluate_boxes(flat, 0, 0.6).ok);
  std::vector<Eigen::Vector3f> nan_cloud(500, Eigen::Vector3f::Constant(NAN));
  EXPECT_FALSE(evaluate_boxes(nan_cloud, 0.4, 0.6).ok);
}

TEST(BoxEvaluation, ALargerRidgeIsNotTakenForABox) {
  // Where the MAV hovered with a wrong height, a long thin ridge of "ground" stands up: it
  // has more points than either box, but not a box's size.
  auto cloud = scene({{{4, -0.45, 0}, 0.0}, {{4, 0.45, 0}, 0.0}}, {0.6, 0.4, 0.3}, 0.01);
  std::mt19937 random(9);
  std::uniform_real_distribution<double> along(-1.4, 1.4), across(-0.01, 0.01);
  for (int i = 0; i < 20000; ++i) cloud.emplace_back(1.5 + across(random), along(random), 0.3);
  const BoxEvaluation result = evaluate_boxes(cloud, 0.4, 0.6);
  ASSERT_TRUE(result.ok) << result.message;
  for (const auto& box : result.boxes) EXPECT_NEAR(box.centre.x(), 4.0, 0.02);
  EXPECT_GT(result.mean_performance_percent, 98.0);
}

namespace {

// A box-sized plateau 0.25 m up with no sides: around it, 5 to 20 cm beyond its edges, the
// ground stands 0.07 m up (above half the 0.1 m cut, below the cut), as around the crown of a
// mound that the local ground planes cut off.
double plateau_without_sides(double x, double y) {
  const double dx = std::abs(x - 2), dy = std::abs(y);
  if (dx <= 0.3 && dy <= 0.2) return 0.25;
  return dx <= 0.5 && dy <= 0.4 ? 0.07 : 0.0;
}

}  // namespace

TEST(BoxEvaluation, ObjectsWithSidesComeFirst) {
  // The plateau matches the boxes' footprint exactly, the boxes (0.62 x 0.42 m) less well:
  // ranked by size alone the plateau would be taken for a box.
  const auto cloud =
      scene({{{4.5, -0.45, 0}, 0.0}, {{4.5, 0.45, 0}, 0.0}}, {0.62, 0.42, 0.3}, 0.01, plateau_without_sides);
  const BoxEvaluation result = evaluate_boxes(cloud, 0.4, 0.6);
  ASSERT_TRUE(result.ok) << result.message;
  ASSERT_EQ(result.boxes.size(), 2u);
  for (const auto& box : result.boxes) EXPECT_NEAR(box.centre.x(), 4.5, 0.02);
}

TEST(BoxEvaluation, TooFewObjectsWithSidesStillGiveAMeasurement) {
  const auto cloud = scene({{{4.5, 0.45, 0}, 0.0}}, {0.62, 0.42, 0.3}, 0.01, plateau_without_sides);
  const BoxEvaluation result = evaluate_boxes(cloud, 0.4, 0.6);
  ASSERT_TRUE(result.ok) << result.message;
  ASSERT_EQ(result.boxes.size(), 2u);
  const double xs[] = {result.boxes[0].centre.x(), result.boxes[1].centre.x()};
  EXPECT_NEAR(std::min(xs[0], xs[1]), 2.0, 0.02);  // the plateau, measured since nothing better stands there
  EXPECT_NEAR(std::max(xs[0], xs[1]), 4.5, 0.02);
}

TEST(BoxEvaluation, AStripWithABoxsAreaIsNotTakenForABox) {
  // As along a step's edge that the local ground planes cut off: 1.1 x 0.22 m, a box's area
  // (nearer it than the 0.62 x 0.42 m boxes), twice its length.
  const auto strip = [](double x, double y) { return std::abs(x - 2) <= 0.11 && std::abs(y) <= 0.55 ? 0.3 : 0.0; };
  const auto cloud = scene({{{4.5, -0.45, 0}, 0.0}, {{4.5, 0.45, 0}, 0.0}}, {0.62, 0.42, 0.3}, 0.01, strip);
  const BoxEvaluation result = evaluate_boxes(cloud, 0.4, 0.6);
  ASSERT_TRUE(result.ok) << result.message;
  ASSERT_EQ(result.boxes.size(), 2u);
  for (const auto& box : result.boxes) EXPECT_NEAR(box.centre.x(), 4.5, 0.02);
}
