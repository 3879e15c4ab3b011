// Algorithm 1 of the room thesis: keep points in x-y bins that are dense and tall (walls),
// drop sparse or flat ones (floor, ceiling, low furniture, clutter), and drop points
// nearer than a minimum range to the scanner.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace scanbus::room_measurement {

struct HistogramFilterSettings {
  int bins = 100;                // per axis, over the cloud's x-y extent (thesis: 100 x 100)
  double min_range = 0.3;        // m from the scanner (the origin): its own mount; the thesis's 1.2 m
                                 // drops every wall of a closet and the near walls of a corner
  int min_points = 10;           // per bin, at reference_range
  double reference_range = 2.0;  // m: farther bins need fewer points, (reference_range / range)^2 of
                                 // min_points (at least 3): a scanner's fixed angular steps put that
                                 // many fewer points on a wall column; nearer bins need min_points
  double min_z_spread = 1.0;     // m between a bin's lowest and highest point
};

std::vector<Eigen::Vector3f> histogram_filter(const std::vector<Eigen::Vector3f>& points,
                                              const HistogramFilterSettings& settings);

}  // namespace scanbus::room_measurement
