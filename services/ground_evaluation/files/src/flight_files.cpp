#include "scanbus/ground_evaluation/flight_files.hpp"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <stdexcept>

#include "scanbus/cloud_dem/geotiff.hpp"
#include "scanbus/cloud_io/cloud_files.hpp"
#include "scanbus/plot/cloud_picture.hpp"

namespace scanbus::ground_evaluation {

namespace {

void write_heights(const std::string& path, const std::vector<HeightSample>& samples) {
  std::ofstream file(path);
  file << "stamp,truth,barometer,scan_matcher,fused,gps,clearance,fused_sigma,fused_immediate,fused_immediate_sigma\n";
  for (const auto& sample : samples)
    file << std::fixed << std::setprecision(4) << sample.stamp << ',' << sample.truth << ',' << sample.height[0] << ','
         << sample.height[1] << ',' << sample.height[2] << ',' << sample.height[3] << ',' << sample.clearance << ','
         << sample.fused_sigma << ',' << sample.immediate << ',' << sample.immediate_sigma << '\n';
  file.close();
  if (!file) throw std::runtime_error("cannot write " + path);
}

void write_cloud(const std::string& path, const std::string& title, const std::vector<Eigen::Vector3f>& cloud) {
  std::vector<CloudPoint> points;
  points.reserve(cloud.size());
  for (const auto& p : cloud) points.push_back({p, 0.0f});
  cloud_io::write_pcd(path + ".pcd", points);
  plot::write_cloud_picture(path + ".png", points, title, plot::CloudView::Top, false);
}

}  // namespace

void write_flight_files(const std::string& folder, const std::string& flight, const FlightEvaluation& evaluation,
                        const sensor_replay::MavLog& log) {
  std::string stem = flight.substr(flight.find_last_of('/') + 1);
  std::replace(stem.begin(), stem.end(), ' ', '_');
  const std::string base = folder + "/" + stem;
  write_heights(base + "_heights.csv", evaluation.heights);
  for (int source = 0; source < kHeightSources; ++source) {
    if (evaluation.cloud[source].empty()) continue;
    write_cloud(base + "_" + kHeightSourceNames[source], flight + ", height from " + kHeightSourceNames[source],
                evaluation.cloud[source]);
  }
  if (evaluation.elevation.filled() == 0) return;
  const auto& origin = log.meta_of("origin", 3);
  cloud_dem::write_geotiff(base + "_fused_dem.tif", evaluation.elevation, {origin[0], origin[1], origin[2]});
}

}  // namespace scanbus::ground_evaluation
