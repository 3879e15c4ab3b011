// The MAV paper's quantitative check of a ground model (section 4.1): boxes of known size
// stand on the ground; find them in the cloud (the paper's ground is flat: here the ground is
// removed as a plane per half-metre cell, so boxes on a slope or a mound are found the same
// way; Euclidean clusters, the objects with sides and at most 1.5 boxes long nearest the
// boxes' known footprint area, then the others), fit each one's footprint rectangle and
// compare its width/length ratio with the truth:
// E = |ratio_measured - ratio_actual| / ratio_actual * 100 %, P = 100 % - E.
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace scanbus::ground_evaluation {

struct BoxSearchSettings {
  size_t boxes = 2;                 // how many boxes stand there (the paper: two)
  double ground_threshold = 0.05;   // m: RANSAC inlier distance of the ground plane
  double min_height = 0.1;          // m above the ground: lower points belong to the ground (raised
                                    // to four sigmas of the ground's own spread when that is more)
  double cluster_tolerance = 0.05;  // m between neighbouring points of one box
  size_t min_cluster_points = 30;
  double top_band = 0.04;  // m: a box's footprint is drawn from its points this near the
                           // plane of its top (its sides, seen at a slant, would widen it)
  double noise = 0.02;     // m: a first guess of the points' noise (estimated with the sides)
};

struct BoxMeasurement {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // m, map frame
  double yaw = 0;                                    // rad, of the length axis
  double length = 0, width = 0, height = 0;          // m: length the longer side
  size_t points = 0;
  double error_percent = 0, performance_percent = 0;  // E and P of this box
};

struct BoxEvaluation {
  bool ok = false;
  std::string message;  // why not, when not ok
  double ratio_actual = 0;
  std::vector<BoxMeasurement> boxes;  // objects with sides nearest the boxes' size first
  double mean_performance_percent = 0;
  size_t ground_points = 0;
  double ground_sigma = 0;  // m, robust spread of the ground's heights about the ground under them
};

// `truth_width` and `truth_length` are the boxes' true footprint (any order: width is the
// shorter). Never throws on a cloud: a cloud without the boxes gives ok = false and why.
BoxEvaluation evaluate_boxes(const std::vector<Eigen::Vector3f>& cloud, double truth_width, double truth_length,
                             const BoxSearchSettings& settings = {});

// The rectangle of a footprint: the orientation of the least bounding area, and the sides
// along it that best explain the points under noise (first guess `noise`, m).
struct Footprint {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double yaw = 0, length = 0, width = 0;
};
Footprint fit_footprint(const std::vector<Eigen::Vector2d>& points, double noise);

}  // namespace scanbus::ground_evaluation
