// The Ceres height fusion per update (one scan-matcher change and a scan's 361 ground
// returns at 30 Hz, a barometer sample and a GPS altitude at 10 Hz, a 3 s window,
// marginalisation as the window slides) on one core, flying at 0.5 m/s back and forth over
// 12 m. Target (issues 6, 19): under 1 ms per update. Measured once the window is full;
// solve_every 3 (the default: the newest node is propagated in between) and 1 (a solve at
// every scan); with the ground returns (the default) and without.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "scanbus/atmosphere.hpp"
#include "scanbus/pose_estimation/height_fusion.hpp"
#include "scanbus/pose_estimation/pose_estimator.hpp"

namespace {

using namespace scanbus::pose_estimation;

double height_at(double t) { return 3 + 0.4 * std::sin(t / 3); }
double x_at(double t) { return 6 - 6 * std::cos(t * M_PI / 24); }

void BM_HeightFusionUpdate(benchmark::State& state) {
  FusionSettings settings;
  settings.window = 3.0;
  settings.solve_every = static_cast<int>(state.range(0));
  const bool with_ground = state.range(1) != 0;
  HeightFusion fusion(settings);
  std::mt19937 random(3);
  std::normal_distribution<double> gauss(0, 1);
  long k = 0;
  const auto step = [&] {
    const double t = k / 30.0;
    if (k % 3 == 0) {
      fusion.add_barometer(t, height_at(t) + 0.3 * gauss(random));
      fusion.add_gps(t, height_at(t) + 0.02 * gauss(random), 0.04);
    }
    const double change = height_at(t) - height_at(t - 1 / 30.0) + 0.003 * gauss(random);
    std::vector<GroundReturn> ground;
    for (int i = 0; with_ground && i <= 360; ++i) {
      const double across = height_at(t) * std::tan((i - 180) * 0.25 * M_PI / 180);
      ground.push_back({{x_at(t), across}, height_at(t) + 0.02 * gauss(random)});
    }
    benchmark::DoNotOptimize(fusion.add_node(t, k > 0 ? std::optional<double>(change) : std::nullopt, ground));
    benchmark::DoNotOptimize(fusion.take_settled());  // as the node does: their sigmas are part of the cost
    ++k;
  };
  while (k < 300) step();  // 10 s: the window is full and sliding
  for (auto _ : state) step();
  state.counters["nodes_in_window"] = static_cast<double>(fusion.nodes_in_window());
  state.counters["ground_cells"] = static_cast<double>(fusion.ground_cells());
}
BENCHMARK(BM_HeightFusionUpdate)
    ->ArgNames({"solve_every", "ground"})
    ->Args({3, 1})
    ->Args({1, 1})
    ->Args({3, 0})
    ->Unit(benchmark::kMicrosecond);

// The whole estimator per scan: IMU, GPS and barometer at 10 Hz, a match and its scan (361
// rays over flat ground) at 30 Hz, the pose out (GeographicLib, interpolation, the returns
// placed on the map, fusion). The MAV hovers over the origin.
void BM_PoseEstimatorScan(benchmark::State& state) {
  PoseEstimatorSettings settings;
  settings.origin = {52.5, 13.4, 34.0};
  settings.laser_in_body.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));  // looking down
  PoseEstimator estimator(settings);
  constexpr double kStep = 0.25 * M_PI / 180;
  std::vector<float> ranges(361);
  std::mt19937 random(3);
  std::normal_distribution<double> gauss(0, 1);
  long k = 0;
  const auto step = [&] {
    const double t = k / 30.0;
    if (k % 3 == 0) {
      estimator.add_imu(t, Eigen::Quaterniond::Identity());
      estimator.add_fix(t, 52.5, 13.4, 34.0 + height_at(t), 0.01, 0.02);
      estimator.add_pressure(t, scanbus::pressure_at_altitude(34.0 + height_at(t) + 0.3 * gauss(random)));
    }
    for (size_t i = 0; i < ranges.size(); ++i)
      ranges[i] =
          static_cast<float>(height_at(t) / std::cos((static_cast<double>(i) - 180) * kStep) + 0.02 * gauss(random));
    estimator.add_scan({t, -M_PI / 4, kStep, 0.1, 30, ranges});
    estimator.add_match(t, Eigen::Vector2d(height_at(t - 1 / 30.0) - height_at(t), 0));
    benchmark::DoNotOptimize(estimator.take_ready());
    benchmark::DoNotOptimize(estimator.take_settled());
    ++k;
  };
  while (k < 300) step();
  for (auto _ : state) step();
}
BENCHMARK(BM_PoseEstimatorScan)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
