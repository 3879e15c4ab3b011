#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scanbus/cloud_io/cloud_files.hpp"
#include "scanbus/ground_evaluation/flight_files.hpp"

using namespace scanbus;
using namespace scanbus::ground_evaluation;

namespace {

FlightEvaluation two_poses_and_a_fused_cloud() {
  FlightEvaluation evaluation;
  for (double stamp : {0.0, 0.1}) {
    HeightSample sample;
    sample.stamp = stamp;
    sample.truth = 3;
    evaluation.heights.push_back(sample);
  }
  evaluation.cloud[static_cast<int>(HeightSource::Fused)] = {{0, 0, 0}, {1, 0, 0.1f}, {0, 1, 0.2f}};
  return evaluation;
}

// One per process: ctest runs each test as a process beside another, and gtest's random seed
// (the time in milliseconds) once gave two of them the same folder, which the first to finish
// removed under the other (a sanitizer run in CI: "not a readable pcd file").
struct TemporaryFolder {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("flight_files_test_" + std::to_string(::getpid()));
  TemporaryFolder() { std::filesystem::create_directories(path); }
  ~TemporaryFolder() { std::filesystem::remove_all(path); }
};

}  // namespace

TEST(FlightFiles, EveryHeightAndTheCloudsOfTheHeightsThereAre) {
  TemporaryFolder folder;
  write_flight_files(folder.path.string(), "scenario IV", two_poses_and_a_fused_cloud(), {});
  std::ifstream csv(folder.path / "scenario_IV_heights.csv");
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 3);  // the header and one per pose
  EXPECT_EQ(cloud_io::read_cloud((folder.path / "scenario_IV_fused.pcd").string(), 1).size(), 3u);
  EXPECT_TRUE(std::filesystem::exists(folder.path / "scenario_IV_fused.png"));
  EXPECT_FALSE(std::filesystem::exists(folder.path / "scenario_IV_barometer.pcd"));  // no cloud, no file
  EXPECT_FALSE(std::filesystem::exists(folder.path / "scenario_IV_fused_dem.tif"));  // no grid cells
}

TEST(FlightFiles, ALogsFolderPartIsNotPartOfTheName) {
  TemporaryFolder folder;
  write_flight_files(folder.path.string(), "/data/flights/log 7.txt", two_poses_and_a_fused_cloud(), {});
  EXPECT_TRUE(std::filesystem::exists(folder.path / "log_7.txt_heights.csv"));
}

TEST(FlightFiles, AFolderThatCannotBeWrittenIsNamed) {
  try {
    write_flight_files("/nonexistent/folder", "scenario I", two_poses_and_a_fused_cloud(), {});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/folder/scenario_I_heights.csv"), std::string::npos) << e.what();
  }
}

TEST(FlightFiles, AnElevationGridNeedsTheLogsOrigin) {
  TemporaryFolder folder;
  FlightEvaluation evaluation = two_poses_and_a_fused_cloud();
  auto& grid = evaluation.elevation;
  grid.cell_size = 1;
  grid.columns = grid.rows = 1;
  grid.height = {1};
  grid.stdev = {0};
  grid.count = {5};
  ASSERT_EQ(grid.filled(), 1u);
  EXPECT_THROW(write_flight_files(folder.path.string(), "real", evaluation, {}), sensor_replay::MavLogError);
  sensor_replay::MavLog log;
  log.meta["origin"] = {47.0, 8.0, 400.0};
  write_flight_files(folder.path.string(), "real", evaluation, log);
  EXPECT_TRUE(std::filesystem::exists(folder.path / "real_fused_dem.tif"));
}
