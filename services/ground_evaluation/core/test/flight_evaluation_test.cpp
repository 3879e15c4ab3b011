#include <gtest/gtest.h>

#include <cstdio>
#include <tuple>
#include <vector>

#include "scanbus/ground_evaluation/flight_evaluation.hpp"
#include "scanbus/mav_sim/flight.hpp"
#include "scanbus/mav_sim/terrain.hpp"
#include "scanbus/pose_estimation/pose_estimator.hpp"

using namespace scanbus;
using namespace scanbus::ground_evaluation;

TEST(FlightEvaluation, TheMavMatcherIsConfigMavScanMatcher) {
  // The compiled-in config/mav/scan_matcher.yaml, not the defaults: its section was found.
  const auto mav = mav_matcher_settings();
  const scan_matcher::MatcherSettings defaults;
  EXPECT_NEAR(mav.opening, M_PI / 2, 1e-12);
  EXPECT_NE(mav.opening, defaults.opening);
  EXPECT_FALSE(mav.constant_velocity);
  EXPECT_TRUE(defaults.constant_velocity);
  EXPECT_EQ(mav.map_keyframes, 1);
  EXPECT_NE(mav.map_keyframes, defaults.map_keyframes);
}

TEST(FlightEvaluation, TheDeployedFusionIsTheEvaluatedOne) {
  // config/services/pose_estimation.yaml against the defaults `scanbus eval mav` runs with.
  const auto deployed = pose_estimation::pose_estimator_settings_from_config(
                            Config::load(std::string(SCANBUS_SOURCE_DIR) + "/config/services/pose_estimation.yaml")
                                .section("pose_estimation"))
                            .fusion;
  const pose_estimation::FusionSettings evaluated;
  for (const auto& [name, a, b] : std::vector<std::tuple<const char*, double, double>>{
           {"window", deployed.window, evaluated.window},
           {"baro_sigma", deployed.baro_sigma, evaluated.baro_sigma},
           {"baro_gate_time", deployed.baro_gate_time, evaluated.baro_gate_time},
           {"bias_random_walk", deployed.bias_random_walk, evaluated.bias_random_walk},
           {"bias_spacing", deployed.bias_spacing, evaluated.bias_spacing},
           {"initial_bias_sigma", deployed.initial_bias_sigma, evaluated.initial_bias_sigma},
           {"gps_wander_time", deployed.gps_wander_time, evaluated.gps_wander_time},
           {"change_sigma", deployed.change_sigma, evaluated.change_sigma},
           {"change_loss", deployed.change_loss, evaluated.change_loss},
           {"change_gate", deployed.change_gate, evaluated.change_gate},
           {"height_walk", deployed.height_walk, evaluated.height_walk},
           {"gate_memory", deployed.gate_memory, evaluated.gate_memory},
           {"solve_every", double(deployed.solve_every), double(evaluated.solve_every)},
           {"cell_size", deployed.cell_size, evaluated.cell_size},
           {"min_cell_returns", double(deployed.min_cell_returns), double(evaluated.min_cell_returns)},
           {"clearance_sigma", deployed.clearance_sigma, evaluated.clearance_sigma},
           {"clearance_loss", deployed.clearance_loss, evaluated.clearance_loss},
           {"clearance_gate", deployed.clearance_gate, evaluated.clearance_gate},
           {"ground_gradient_sigma", deployed.ground_gradient_sigma, evaluated.ground_gradient_sigma},
           {"max_corners", double(deployed.max_corners), double(evaluated.max_corners)},
           {"origin_on_ground", double(deployed.origin_on_ground), double(evaluated.origin_on_ground)},
           {"origin_sigma", deployed.origin_sigma, evaluated.origin_sigma}})
    EXPECT_DOUBLE_EQ(a, b) << name;
}

TEST(FlightEvaluation, AShortFlightGivesAPosePerScanAndTheFusionBeatsTheBarometer) {
  mav_sim::FlightSettings settings;
  settings.duration = 20;
  const FlightEvaluation result = evaluate_flight(mav_sim::simulate_flight(settings), {});
  EXPECT_EQ(result.scans, 600u);
  EXPECT_EQ(result.poses, result.scans);
  EXPECT_EQ(result.heights.size(), result.poses);
  EXPECT_LT(result.height_rmse[static_cast<int>(HeightSource::Fused)],
            0.5 * result.height_rmse[static_cast<int>(HeightSource::Barometer)]);
  EXPECT_FALSE(result.has_boxes);
  EXPECT_GT(result.cloud[0].size(), 600u * 300);  // most of each scan's 361 rays hit the ground
}

TEST(FlightEvaluation, TheCloudIsPlacedByTheSettledHeightsOrTheFirstSolvedOnes) {
  mav_sim::FlightSettings flight;
  flight.duration = 20;
  const auto log = mav_sim::simulate_flight(flight);
  FlightEvaluationSettings settings;
  for (const bool settled : {true, false}) {
    settings.settled_heights = settled;
    const FlightEvaluation result = evaluate_flight(log, settings);
    ASSERT_EQ(result.heights.size(), 600u);  // every pose, settled or not
    size_t same = 0;
    for (const auto& h : result.heights) same += h.height[static_cast<int>(HeightSource::Fused)] == h.immediate;
    std::printf("%s: %zu of 600 fused heights equal to the first solve; RMSE %.4f m, first solved %.4f m\n",
                settled ? "settled" : "first solved", same, result.height_rmse[static_cast<int>(HeightSource::Fused)],
                result.immediate_rmse);
    if (settled) {
      EXPECT_LT(same, 60u);  // solved again with the 3 s after them
    } else {
      EXPECT_EQ(same, 600u);
      EXPECT_DOUBLE_EQ(result.height_rmse[static_cast<int>(HeightSource::Fused)], result.immediate_rmse);
    }
  }
}

TEST(GroundModelError, ScoresWhereTheGroundIsKnown) {
  const std::vector<Eigen::Vector3f> cloud{{0, 0, 0.1f}, {1, 0, 0.1f}, {2, 0, -0.1f}, {3, 0, 0.3f}, {5, 0, 9.0f}};
  const auto truth = [](const Eigen::Vector2d& xy) -> std::optional<double> {
    if (xy.x() > 4) return std::nullopt;  // an edge: not scored
    return 0.0;
  };
  const GroundModelError error = ground_model_error(cloud, truth);
  EXPECT_EQ(error.points, 4u);
  EXPECT_NEAR(error.rmse, std::sqrt((0.01 + 0.01 + 0.01 + 0.09) / 4), 1e-6);
  EXPECT_NEAR(error.bias, 0.1, 1e-6);
  EXPECT_NEAR(error.median, 0.1, 1e-6);
  EXPECT_NEAR(error.p95, 0.3, 1e-6);
  EXPECT_EQ(ground_model_error(cloud, [](const Eigen::Vector2d&) { return std::optional<double>(); }).points, 0u);
  EXPECT_TRUE(std::isnan(error.slope_error));  // one line of points: no plane
}

// A cloud flattened to 90 % of the terrain's tilt is 10 % off; level ground has no relative error.
TEST(GroundModelError, ComparesTheCloudsTiltWithTheTerrains) {
  const auto sloped = [](const Eigen::Vector2d& xy) -> std::optional<double> { return 0.05 * xy.x() - 0.02 * xy.y(); };
  std::vector<Eigen::Vector3f> cloud;
  for (int x = 0; x < 10; ++x)
    for (int y = -2; y <= 2; ++y) cloud.emplace_back(x, y, 0.9 * *sloped({x, y}) + 0.3);
  const GroundModelError error = ground_model_error(cloud, sloped);
  EXPECT_NEAR(error.true_slope.x(), 0.05, 1e-9);
  EXPECT_NEAR(error.true_slope.y(), -0.02, 1e-9);
  EXPECT_NEAR(error.slope.x(), 0.045, 1e-6);
  EXPECT_NEAR(error.slope_error, 0.1, 1e-5);
  const GroundModelError level =
      ground_model_error(cloud, [](const Eigen::Vector2d&) { return std::optional<double>(0.0); });
  EXPECT_TRUE(std::isnan(level.slope_error));
  EXPECT_NEAR(level.slope.x(), 0.045, 1e-6);
}

// A simulated flight evaluated with its true ground (points 0.1 m from an edge not scored).
static FlightEvaluation evaluate_against_its_ground(const sensor_replay::MavLog& log) {
  FlightEvaluationSettings evaluation;
  evaluation.true_ground = mav_sim::scored_ground_of_log(log);
  return evaluate_flight(log, evaluation);
}

// Over flat ground the fused cloud lies within centimetres of the truth; over a terrain the
// same evaluation measures how far the model is from it (issue 19's figures).
TEST(FlightEvaluation, TheGroundModelIsScoredAgainstTheSimulatedGround) {
  mav_sim::FlightSettings settings;
  settings.duration = 20;
  const auto log = mav_sim::simulate_flight(settings);
  const FlightEvaluation result = evaluate_against_its_ground(log);
  ASSERT_TRUE(result.has_ground);
  const auto& fused = result.ground[static_cast<int>(HeightSource::Fused)];
  EXPECT_EQ(fused.points, result.cloud[static_cast<int>(HeightSource::Fused)].size());  // flat: every point scored
  EXPECT_LT(fused.rmse, 0.1);
  EXPECT_LT(fused.rmse, 0.5 * result.ground[static_cast<int>(HeightSource::Barometer)].rmse);
  EXPECT_FALSE(evaluate_flight(log, {}).has_ground);
}

// The cloud at the true height sets the floor no height estimate goes under: without sensor
// errors it lies on the ground; with them it keeps the laser's and the attitude's part. Built
// from the log's TRUTH heights, not an estimate: truths raised by 0.3 m raise it alone.
TEST(FlightEvaluation, TheCloudAtTheTrueHeightShowsWhatTheOtherSensorsLeave) {
  mav_sim::FlightSettings settings;
  settings.duration = 20;
  settings.noise_scale = 0;
  auto log = mav_sim::simulate_flight(settings);
  const FlightEvaluation exact = evaluate_against_its_ground(log);
  EXPECT_EQ(exact.ground_at_true_height.points, exact.ground[static_cast<int>(HeightSource::Fused)].points);
  EXPECT_LT(exact.ground_at_true_height.rmse, 0.002);
  for (auto& truth : log.truths) truth.position.z() += 0.3;
  const FlightEvaluation raised = evaluate_against_its_ground(log);
  EXPECT_NEAR(raised.ground_at_true_height.bias, 0.3, 0.002);
  EXPECT_NEAR(raised.ground[static_cast<int>(HeightSource::Fused)].bias,
              exact.ground[static_cast<int>(HeightSource::Fused)].bias, 1e-9);
  settings.noise_scale = 1;
  const FlightEvaluation flown = evaluate_against_its_ground(mav_sim::simulate_flight(settings));
  EXPECT_GT(flown.ground_at_true_height.rmse, 0.01);  // the laser's 2 cm range noise at least in part
  EXPECT_LT(flown.ground_at_true_height.rmse, flown.ground[static_cast<int>(HeightSource::Fused)].rmse);
}

// The fused cloud's elevation grid over a slope with a mound: every cell of the grid holds
// the mean of its returns, and the cells follow the terrain (not a flat ground).
TEST(FlightEvaluation, TheElevationGridFollowsTheTerrain) {
  mav_sim::FlightSettings settings;
  settings.duration = 20;
  settings.terrain.slope = {0.06, -0.03};
  settings.terrain.mounds = {{{5, 0}, 1.5, 0.3}};
  const FlightEvaluation result = evaluate_against_its_ground(mav_sim::simulate_flight(settings));
  ASSERT_TRUE(result.has_ground);
  const auto& grid = result.elevation;
  ASSERT_GT(grid.filled(), 50u);
  size_t counted = 0;
  for (uint32_t count : grid.count) counted += count;
  EXPECT_GT(counted,
            result.cloud[static_cast<int>(HeightSource::Fused)].size() * 9 / 10);  // sparse edge cells left out
  const auto& error = result.elevation_error;
  std::printf("elevation grid: %zu cells, RMSE %.3f m, p95 %.3f m, bias %+.3f m, slope %.4f %.4f (true %.4f %.4f)\n",
              error.points, error.rmse, error.p95, error.bias, error.slope.x(), error.slope.y(), error.true_slope.x(),
              error.true_slope.y());
  EXPECT_EQ(error.points, grid.filled());
  EXPECT_LT(error.rmse, 0.1);
  EXPECT_LT(error.slope_error, 0.15);  // the grid keeps the terrain's tilt
  EXPECT_LT(error.rmse, result.ground[static_cast<int>(HeightSource::Fused)].rmse + 0.02);
}

// Scenario IV over a slope with a mound beside the boxes: the boxes are found on the ground
// under them and measured, in their tops, to centimetres.
TEST(FlightEvaluation, TheBoxesAreFoundOnSlopedGround) {
  mav_sim::FlightSettings settings;
  settings.scenario = 4;
  settings.duration = 48;  // two rounds over the boxes
  settings.terrain.slope = {0.052, 0};
  settings.terrain.mounds = {{{6, 0.5}, 3, 0.4}, {{2, -1}, 1, -0.25}};
  settings.terrain.roughness = 0.02;
  const FlightEvaluation result = evaluate_flight(mav_sim::simulate_flight(settings), {});
  const BoxEvaluation& boxes = result.boxes[static_cast<int>(HeightSource::Fused)];
  ASSERT_TRUE(boxes.ok) << boxes.message;
  for (const auto& box : boxes.boxes) {
    std::printf("box at (%.3f, %.3f): %.3f x %.3f m\n", box.centre.x(), box.centre.y(), box.length, box.width);
    EXPECT_NEAR(box.centre.x(), 4, 0.05);
    EXPECT_NEAR(std::abs(box.centre.y()), 0.45, 0.05);
    // Two passes only: one box's length came out 0.586 m with the GPS bias a random walk, 0.580
    // m since it is Gauss-Markov (0f18494), just past the 2 cm this asked first. A crown or a strip
    // taken for a box is decimetres off.
    EXPECT_NEAR(box.length, 0.6, 0.03);
    EXPECT_NEAR(box.width, 0.4, 0.02);
  }
}

TEST(FlightEvaluation, ALogWithoutItsMountOrTruthIsNamed) {
  mav_sim::FlightSettings settings;
  settings.duration = 1;
  auto log = mav_sim::simulate_flight(settings);
  log.truths.clear();
  EXPECT_THROW(evaluate_flight(log, {}), sensor_replay::MavLogError);
  log.meta.erase("laser_mount");
  try {
    evaluate_flight(log, {});
    FAIL();
  } catch (const sensor_replay::MavLogError& e) {
    EXPECT_NE(std::string(e.what()).find("laser_mount"), std::string::npos) << e.what();
  }
}

// The simulated unit of seed 6 has its laser turned 0.7 degrees in its scan plane: a
// hover-turn over level ground finds it, and a flight over a 5 % slope placed with it keeps
// the terrain's tilt, which the mount as drawn loses by more than a tenth.
TEST(ScanPlaneCalibration, AHoverTurnFindsTheSimulatedUnitsTurnAndTheTiltComesBack) {
  mav_sim::FlightSettings hover;
  hover.seed = 6;
  hover.pattern = mav_sim::FlightPattern::hover_turn;
  hover.duration = 91;  // five whole turns
  const auto turning = mav_sim::simulate_flight(hover);
  const auto calibration = calibrate_scan_plane(turning);
  ASSERT_TRUE(calibration.ok) << calibration.status;
  const double truth = turning.meta_of("true_laser_misalignment", 3)[2];
  EXPECT_GT(std::abs(truth), 0.01);
  EXPECT_NEAR(calibration.rotation, truth, 3 * calibration.sigma + 1e-4);

  mav_sim::FlightSettings flight;
  flight.seed = 6;
  flight.duration = 40;
  flight.terrain =
      mav_sim::load_terrain(std::string(SCANBUS_SOURCE_DIR) + "/config/terrain/validation/slope5_diagonal.yaml");
  const auto log = mav_sim::simulate_flight(flight);
  FlightEvaluationSettings as_drawn;
  as_drawn.true_ground = mav_sim::scored_ground_of_log(log);
  FlightEvaluationSettings calibrated = as_drawn;
  calibrated.scan_plane_rotation = calibration.rotation;
  const auto fused = static_cast<int>(HeightSource::Fused);
  EXPECT_GT(evaluate_flight(log, as_drawn).ground[fused].slope_error, 0.1);
  EXPECT_LT(evaluate_flight(log, calibrated).ground[fused].slope_error, 0.05);
}

// Over steps and rough ground each turn sees the same relief from a slightly drifted spot, and
// the turns' spread no longer holds the error: refused, with the reason.
TEST(ScanPlaneCalibration, AHoverTurnOverUnevenGroundIsRefused) {
  mav_sim::FlightSettings hover;
  hover.pattern = mav_sim::FlightPattern::hover_turn;
  hover.duration = 56;  // three whole turns, the least that is measured
  hover.terrain =
      mav_sim::load_terrain(std::string(SCANBUS_SOURCE_DIR) + "/config/terrain/validation/steps_rough.yaml");
  const auto calibration = calibrate_scan_plane(mav_sim::simulate_flight(hover));
  EXPECT_FALSE(calibration.ok);
  EXPECT_NE(calibration.status.find("not level and even"), std::string::npos) << calibration.status;
}
