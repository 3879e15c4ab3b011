#include <gtest/gtest.h>

#include "scanbus/ground_evaluation/flight_evaluation.hpp"
#include "scanbus/mav_sim/flight.hpp"

using namespace scanbus;
using namespace scanbus::ground_evaluation;

TEST(FlightEvaluation, TheMavDeploymentMatchesAsTheEvaluationDoes) {
  // config/mav/scan_matcher.yaml and mav_matcher_settings() must not drift apart: the DDS
  // pipeline's figures are compared with the in-process ones.
  const Config section = Config::load(std::string(SCANBUS_SOURCE_DIR) + "/config/mav/scan_matcher.yaml")
                             .section("scan_matcher")
                             .section("matcher");
  const auto deployed = scan_matcher::matcher_settings_from_config(section);
  const auto evaluated = mav_matcher_settings();
  EXPECT_NEAR(deployed.opening, evaluated.opening, 1e-9);
  EXPECT_DOUBLE_EQ(deployed.max_correspondence, evaluated.max_correspondence);
  EXPECT_DOUBLE_EQ(deployed.range_max, evaluated.range_max);
  EXPECT_DOUBLE_EQ(deployed.trim, evaluated.trim);
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
