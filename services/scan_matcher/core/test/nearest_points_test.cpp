// The map's nearest-point search: a query that moves in small steps, answered from the points
// it found nearby, gives the answer a full search gives.
#include "../src/nearest_points.hpp"

#include <gtest/gtest.h>

#include <random>

namespace scanbus::scan_matcher {
namespace {

// The nearest of `points` within max_distance, by looking at every one.
NearestPoints::Found brute_force(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& query,
                                 double max_distance) {
  NearestPoints::Found best{NearestPoints::npos, max_distance * max_distance};
  for (size_t i = 0; i < points.size(); ++i) {
    const double distance_squared = (points[i] - query).squaredNorm();
    if (distance_squared <= best.distance_squared) best = {i, distance_squared};
  }
  return best;
}

TEST(MovingQuery, AnswersAsASearchOfEveryPointWould) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> place(-5, 5);
  std::vector<Eigen::Vector2d> points;
  // Walls (points 5 cm apart, as the map keeps them) and scattered clutter.
  for (double s = 0; s < 4; s += 0.05) {
    points.emplace_back(-2 + s, 1.0);
    points.emplace_back(2.0, -2 + s);
  }
  for (int i = 0; i < 200; ++i) points.emplace_back(place(random), place(random));
  const NearestPoints map(points);
  std::normal_distribution<double> step(0, 0.01), jump(0, 0.3);
  size_t answered = 0, none = 0;
  for (int walk = 0; walk < 50; ++walk) {
    MovingQuery query;
    Eigen::Vector2d at(place(random), place(random));
    for (int i = 0; i < 40; ++i) {
      // Mostly millimetre steps, as Gauss-Newton's last iterations make, now and then a jump.
      at += i % 10 == 0 ? Eigen::Vector2d(jump(random), jump(random)) : Eigen::Vector2d(step(random), step(random));
      const auto expected = brute_force(points, at, 0.5);
      const auto found = query.nearest(map, at, 0.5);
      ASSERT_EQ(found.index, expected.index) << "walk " << walk << " step " << i;
      if (found.index == NearestPoints::npos) {
        ++none;
        continue;
      }
      EXPECT_DOUBLE_EQ(found.distance_squared, expected.distance_squared);
      ++answered;
    }
  }
  // Both kinds of answer were checked.
  EXPECT_GT(answered, 500u);
  EXPECT_GT(none, 20u);
}

}  // namespace
}  // namespace scanbus::scan_matcher
