#include "cloud_files.hpp"

#include "scanbus/cloud_assembly/cloud_builder.hpp"

#include <cairo.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace scanbus::cli {

namespace {

std::string extension_of(const std::string& path) {
  const size_t dot = path.rfind('.');
  std::string extension = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  return extension;
}

std::vector<Eigen::Vector3f> read_xyz(const std::string& path) {
  std::ifstream in(path);
  std::vector<Eigen::Vector3f> points;
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    // strtof, unlike >>, reads "nan" and "inf": such points are counted, then dropped.
    const char* at = line.c_str();
    float xyz[3];
    for (float& value : xyz) {
      char* end = nullptr;
      value = std::strtof(at, &end);
      if (end == at)
        throw CloudFileError(path + ":" + std::to_string(number) + ": expected three numbers x y z, got '" + line.substr(0, 60) + "'");
      at = end;
    }
    points.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  return points;
}

// PCL's PCD reader crashes on some damaged headers: check the header's shape first (text
// lines of known keys up to DATA), and let PCL read only what looks like a PCD file.
void check_pcd_header(const std::string& path) {
  static const char* kKeys[] = {"VERSION", "FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int number = 1; number <= 32 && std::getline(in, line); ++number) {
    if (line.size() > 4096 || std::any_of(line.begin(), line.end(), [](char c) {
          return static_cast<unsigned char>(c) < 0x09 || static_cast<unsigned char>(c) > 0x7e;
        }))
      throw CloudFileError(path + ": not a readable pcd file (binary bytes in the header, line " + std::to_string(number) + ")");
    if (line.empty() || line[0] == '#') continue;
    const std::string key = line.substr(0, line.find(' '));
    if (std::none_of(std::begin(kKeys), std::end(kKeys), [&](const char* k) { return key == k; }))
      throw CloudFileError(path + ": not a readable pcd file (unknown header key '" + key.substr(0, 20) + "')");
    if (key == "DATA") return;
  }
  throw CloudFileError(path + ": not a readable pcd file (no DATA line in the header)");
}

// Blue (low) to red (high), like RViz's rainbow.

}  // namespace

std::vector<Eigen::Vector3f> read_cloud(const std::string& path, double scale) {
  if (!std::ifstream(path)) throw CloudFileError(path + ": cannot open");
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // our one line says what is wrong
  const std::string extension = extension_of(path);
  std::vector<Eigen::Vector3f> points;
  if (extension == "xyz" || extension == "txt") {
    points = read_xyz(path);
  } else if (extension == "pcd" || extension == "ply") {
    if (extension == "pcd") check_pcd_header(path);
    pcl::PointCloud<pcl::PointXYZ> cloud;
    int status = -1;
    try {
      status = extension == "pcd" ? pcl::io::loadPCDFile(path, cloud) : pcl::PLYReader().read(path, cloud);
    } catch (const std::exception& e) {  // PCL throws on some damage and returns -1 on other
      throw CloudFileError(path + ": not a readable " + extension + " file: " + e.what());
    }
    if (status < 0) throw CloudFileError(path + ": not a readable " + extension + " file");
    points.reserve(cloud.size());
    for (const auto& p : cloud) points.emplace_back(p.x, p.y, p.z);
  } else {
    throw CloudFileError(path + ": unknown format '." + extension + "' (pcd, ply, xyz)");
  }
  if (points.empty()) throw CloudFileError(path + ": no points");
  if (scale != 1.0)
    for (auto& p : points) p *= static_cast<float>(scale);
  return points;
}

void write_pcd(const std::string& path, const std::vector<CloudPoint>& points) {
  pcl::PointCloud<pcl::PointXYZI> cloud;
  for (const auto& point : points) {
    pcl::PointXYZI out;
    out.x = point.position.x();
    out.y = point.position.y();
    out.z = point.position.z();
    out.intensity = point.intensity;
    cloud.push_back(out);  // keeps width x height == size, which the writer checks
  }
  if (cloud.empty() || pcl::io::savePCDFileBinary(path, cloud) != 0)
    throw std::runtime_error(path + ": cannot write PCD" + (cloud.empty() ? " (no points)" : ""));
}


double metres_per_unit(const std::string& unit) {
  if (unit == "mm") return 0.001;
  if (unit == "cm") return 0.01;
  if (unit == "m") return 1.0;
  throw std::invalid_argument("unknown unit '" + unit + "' (m, cm or mm)");
}

void write_cloud_png(const std::string& path, const std::vector<CloudPoint>& points, const std::string& title,
                     CloudView view, bool mark_origin) {
  if (points.empty()) throw std::runtime_error(path + ": no points to draw");
  // Robust extent: a few far returns (through doors, windows) must not shrink the picture.
  Eigen::Vector3f low, high;
  double colour_low = 0, colour_high = 0;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<float> values;
    for (const auto& point : points) values.push_back(point.position[axis]);
    std::sort(values.begin(), values.end());
    low[axis] = values[values.size() * 2 / 100] - 0.5f;
    high[axis] = values[values.size() * 98 / 100] + 0.5f;
    // Colours span nearly all heights: small raised things (boxes on a field) must show.
    if (axis == 2) colour_low = values[values.size() / 100], colour_high = values[values.size() * 999 / 1000];
  }
  // Picture axes: x right; y (top view) or z (side view, looking along +y) up.
  const bool top = view == CloudView::Top;
  const int up = top ? 1 : 2, depth = top ? 2 : 1;
  // 800 pixels wide (or high, when the cloud is taller than wide); the other side fits it.
  const int size = 800, margin = 40;
  const double span = std::max({high.x() - low.x(), high[up] - low[up], 1e-3f});
  const double scale = (size - 2 * margin) / span;
  const int width = static_cast<int>((high.x() - low.x()) * scale) + 2 * margin;
  const int height = std::max(240, static_cast<int>((high[up] - low[up]) * scale) + 2 * margin);
  auto px = [&](double x) { return margin + (x - low.x()) * scale; };
  auto py = [&](double v) { return height - margin - (v - low[up]) * scale; };

  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, std::max(width, 640), height);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
  cairo_set_line_width(cr, 1);
  for (double x = std::ceil(low.x()); x <= high.x(); x += 1.0) {
    cairo_move_to(cr, px(x), margin);
    cairo_line_to(cr, px(x), height - margin);
  }
  for (double v = std::ceil(low[up]); v <= high[up]; v += 1.0) {
    cairo_move_to(cr, margin, py(v));
    cairo_line_to(cr, width - margin, py(v));
  }
  cairo_stroke(cr);
  // The points nearest the viewer drawn last: the highest from above, the lowest y from the side.
  std::vector<const CloudPoint*> order;
  for (const auto& point : points) order.push_back(&point);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) {
    return top ? a->position[depth] < b->position[depth] : a->position[depth] > b->position[depth];
  });
  cairo_rectangle(cr, margin, margin, width - 2 * margin, height - 2 * margin);
  cairo_clip(cr);
  for (const CloudPoint* point : order) {
    const uint32_t colour = cloud_assembly::height_colour(point->position.z(), colour_low, colour_high);
    cairo_set_source_rgb(cr, (colour >> 16) / 255.0, ((colour >> 8) & 0xFF) / 255.0, (colour & 0xFF) / 255.0);
    cairo_arc(cr, px(point->position.x()), py(point->position[up]), 1.6, 0, 2 * M_PI);
    cairo_fill(cr);
  }
  cairo_reset_clip(cr);
  std::string legend = top ? "top view" : "side view (x right, z up)";
  legend += ", grid 1 m, colour = height (blue low, red high)";
  if (mark_origin) {
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_arc(cr, px(0), py(0), 4, 0, 2 * M_PI);
    cairo_fill(cr);
    legend += ", black dot = scanner";
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 14);
  cairo_move_to(cr, margin, 25);
  cairo_show_text(cr, title.c_str());
  cairo_move_to(cr, margin, height - 12);
  cairo_show_text(cr, legend.c_str());
  cairo_destroy(cr);
  const cairo_status_t status = cairo_surface_write_to_png(surface, path.c_str());
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS) throw std::runtime_error(path + ": cannot write PNG: " + cairo_status_to_string(status));
}

}  // namespace scanbus::cli
