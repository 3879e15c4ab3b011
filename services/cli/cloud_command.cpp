// `scanbus cloud save` writes a cloud from the bus to PCD: the latest sample of a
// PointCloud2 topic, or the cloud of a time window asked of cloud_assembly (the MAV
// paper's laser_assembler client). `scanbus cloud render` draws a cloud file coloured by
// height, from above or from the side, as the paper's figures show them. `scanbus cloud dem`
// grids a cloud into an elevation GeoTIFF georeferenced from the map origin.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <mutex>
#include <optional>

#include "cloud_window_client.hpp"
#include "commands.hpp"
#include "scanbus/clock.hpp"
#include "scanbus/cloud_assembly/elevation_grid.hpp"
#include "scanbus/cloud_dem/geotiff.hpp"
#include "scanbus/cloud_io/cloud_files.hpp"
#include "scanbus/messages.hpp"
#include "scanbus/plot/cloud_picture.hpp"
#include "scanbus/point_cloud.hpp"
#include "scanbus/service.hpp"
#include "scanbus/typed_topics.hpp"

namespace scanbus::cli {

namespace {

struct SaveOptions {
  DdsOptions dds;
  std::string topic = topics::kCloudAssembled.name;
  std::vector<double> window;  // begin, end (s since the epoch) for a request
  std::string out;
  double timeout = 10;
};

std::optional<sensor_msgs::msg::PointCloud2> latest_cloud(Participant& participant, const SaveOptions& options) {
  std::mutex mutex;
  std::optional<sensor_msgs::msg::PointCloud2> cloud;
  Reader<sensor_msgs::msg::PointCloud2PubSubType> reader(participant, options.topic,
                                                         [&](const auto& sample, const auto&) {
                                                           std::lock_guard<std::mutex> lock(mutex);
                                                           cloud = sample;
                                                           StopSignal::request();
                                                         });
  StopSignal::wait_for(std::chrono::milliseconds(static_cast<long>(options.timeout * 1000)));
  std::lock_guard<std::mutex> lock(mutex);
  return cloud;
}

int run_save(const SaveOptions& options) {
  StopSignal::install();
  Participant participant(options.dds.settings(), "scanbus/cloud");
  std::string problem = "no sample on " + options.topic + " within " + std::to_string(options.timeout) + " s";
  const auto cloud = options.window.empty()
                         ? latest_cloud(participant, options)
                         : cloud_assembly::request_window_cloud(participant, options.window[0], options.window[1],
                                                                options.timeout, problem);
  if (!cloud) {
    std::cerr << "scanbus cloud save: " << problem << "\n";
    return 1;
  }
  std::vector<CloudPoint> points;
  try {
    points = from_point_cloud2(*cloud);
  } catch (const std::invalid_argument& e) {
    std::cerr << "scanbus cloud save: " << e.what() << "\n";
    return 1;
  }
  cloud_io::write_pcd(options.out, points);
  std::printf("wrote %s: %zu points, frame %s\n", options.out.c_str(), points.size(),
              cloud->header().frame_id().c_str());
  return 0;
}

struct RenderOptions {
  std::string cloud, out, view = "top", unit = "m", title;
};

int run_render(const RenderOptions& options) {
  std::vector<Eigen::Vector3f> positions;
  try {
    positions = cloud_io::read_cloud(options.cloud, cloud_io::metres_per_unit(options.unit));
  } catch (const cloud_io::CloudFileError& e) {
    std::cerr << "scanbus cloud render: " << e.what() << "\n";
    return 2;
  }
  std::vector<CloudPoint> points;
  for (const auto& p : positions)
    if (p.allFinite()) points.push_back({p, 0.0f});
  if (points.empty()) {
    std::cerr << "scanbus cloud render: " << options.cloud << ": no finite points\n";
    return 2;
  }
  plot::write_cloud_picture(options.out, points, options.title.empty() ? options.cloud : options.title,
                            options.view == "top" ? plot::CloudView::Top : plot::CloudView::Side, false);
  std::printf("wrote %s: %zu points, %s view\n", options.out.c_str(), points.size(), options.view.c_str());
  return 0;
}

struct DemOptions {
  std::string cloud, out, unit = "m";
  std::vector<double> origin;  // latitude, longitude (degrees), altitude (m)
  cloud_assembly::ElevationGridSettings grid;
};

int run_dem(const DemOptions& options) {
  try {
    const auto grid = cloud_assembly::grid_elevation(
        cloud_io::read_cloud(options.cloud, cloud_io::metres_per_unit(options.unit)), options.grid);
    cloud_dem::write_geotiff(options.out, grid, {options.origin[0], options.origin[1], options.origin[2]});
    float low = INFINITY, high = -INFINITY;
    for (float h : grid.height)
      if (std::isfinite(h)) low = std::min(low, h), high = std::max(high, h);
    std::printf("wrote %s: %zu x %zu cells of %.2f m, %zu with a height (map z %.3f to %.3f m)\n", options.out.c_str(),
                grid.columns, grid.rows, grid.cell_size, grid.filled(), low, high);
    return 0;
  } catch (const cloud_io::CloudFileError& e) {
    std::cerr << "scanbus cloud dem: " << e.what() << "\n";
  } catch (const cloud_assembly::ElevationGridError& e) {
    std::cerr << "scanbus cloud dem: " << options.cloud << ": " << e.what() << "\n";
  } catch (const cloud_dem::GeoTiffError& e) {
    std::cerr << "scanbus cloud dem: " << e.what() << "\n";
  }
  return 2;
}

}  // namespace

void add_cloud_command(CLI::App& app, int& exit_code) {
  auto* cloud = app.add_subcommand(
      "cloud", "Clouds: save one from the bus, draw one coloured by height, grid one into an elevation GeoTIFF");
  cloud->require_subcommand(1);

  static SaveOptions save;
  auto* saving = cloud->add_subcommand("save",
                                       "Write the latest cloud of a topic, or a time window's cloud asked of "
                                       "cloud_assembly, to PCD");
  saving->add_option("--out", save.out, "PCD file to write")->required();
  saving->add_option("--topic", save.topic, "PointCloud2 topic (latest sample)");
  saving->add_option("--window", save.window, "begin,end in s since the epoch: ask cloud_assembly for that window")
      ->expected(2)
      ->delimiter(',');
  saving->add_option("--timeout", save.timeout, "Seconds to wait")->check(CLI::PositiveNumber);
  add_dds_options(*saving, save.dds);
  on_run(*saving, exit_code, [] { return run_save(save); });

  static RenderOptions render;
  auto* drawing = cloud->add_subcommand("render", "Draw a PCD, PLY or XYZ cloud coloured by height as PNG");
  drawing->add_option("cloud", render.cloud, "Cloud file")->required()->check(CLI::ExistingFile);
  drawing->add_option("--view", render.view, "top or side")->check(CLI::IsMember({"top", "side"}));
  drawing->add_option("--out", render.out, "PNG file to write")->required();
  drawing->add_option("--unit", render.unit, "Unit of the cloud's coordinates")
      ->check(CLI::IsMember({"m", "cm", "mm"}));
  drawing->add_option("--title", render.title, "Title above the picture (default: the file name)");
  on_run(*drawing, exit_code, [] { return run_render(render); });

  static DemOptions dem;
  auto* gridding = cloud->add_subcommand("dem",
                                         "Grid a map-frame cloud (PCD, PLY, XYZ) into an elevation GeoTIFF: height "
                                         "above the WGS84 ellipsoid, spread and count per cell");
  gridding->add_option("cloud", dem.cloud, "Cloud file in the map frame (x east, y north, z up)")
      ->required()
      ->check(CLI::ExistingFile);
  gridding
      ->add_option("--origin", dem.origin,
                   "The map origin's latitude,longitude (degrees) and altitude (m above the "
                   "ellipsoid), as the MAV log's META origin")
      ->required()
      ->expected(3)
      ->delimiter(',');
  gridding->add_option("--out", dem.out, "GeoTIFF file to write")->required();
  gridding->add_option("--cell", dem.grid.cell_size, "Cell size, m")->check(CLI::PositiveNumber);
  gridding->add_option("--min-points", dem.grid.min_points, "Returns a cell needs for a height")
      ->check(CLI::Range(1, 1000000));
  gridding->add_option("--unit", dem.unit, "Unit of the cloud's coordinates")->check(CLI::IsMember({"m", "cm", "mm"}));
  on_run(*gridding, exit_code, [] { return run_dem(dem); });
}

}  // namespace scanbus::cli
