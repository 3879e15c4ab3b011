// Walls as 2D lines fitted to a vertical plane's inliers, and the room's polygon from them.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace scanbus::room_measurement {

// A vertical wall: normal . (x, y) = offset, normal pointing away from the scanner.
struct WallLine {
  Eigen::Vector2d normal;
  double offset = 0;
  double rms = 0;             // m, inliers' distance to the fitted line
  double offset_sigma = 0;    // m, standard error of the offset
  double start = 0, end = 0;  // extent of the inliers along the wall, m, along (-n.y, n.x)
  double z_low = 0, z_high = 0;
  double z_coverage = 0;      // share of 10 cm height slices between z_low and z_high holding inliers
  double length_coverage = 0; // share of 10 cm slots between start and end holding inliers
  std::vector<Eigen::Vector3f> inliers;

  Eigen::Vector2d direction() const { return {-normal.y(), normal.x()}; }
};

// Least-squares line through the inliers' x-y (total least squares: the smallest
// principal axis is the normal). Extents are robust (1st to 99th percentile).
WallLine fit_wall(std::vector<Eigen::Vector3f> inliers);

// Candidates on one line (normals within `angle`, offsets within `same`) are one wall that
// RANSAC split: merged and refitted. A weaker candidate parallel to a stronger one and
// within `tail` of it is the stronger one's noise beyond the RANSAC band: dropped.
std::vector<WallLine> merge_collinear(std::vector<WallLine> walls, double angle, double same, double tail);

struct Polygon {
  std::vector<size_t> walls;               // indices into the candidates, in order around the room
  std::vector<Eigen::Vector2d> corners;    // corners[i] joins walls[i-1] and walls[i]
};

struct PolygonSettings {
  double min_wall_angle_deg = 30;  // neighbours closer to parallel than this cannot meet in a corner
  double min_run_deg = 2;          // a wall seen over less of the turn is clutter
  double max_gap_deg = 40;         // a wider sector with no wall is an open side, not a doorway: no room
  double extent_tolerance = 0.05;  // m: rays just past a wall's inlier extent still hit it
  double corner_margin = 1.0;      // m around the points where corners may lie (Algorithm 2)
};

// The room's walls in order: turning once around the scanner (the origin), the farthest
// wall hit in each direction is the room's (furniture stands in front of walls); then
// neighbours are intersected. Fails with a message when the walls do not close a room.
std::optional<Polygon> room_polygon(const std::vector<WallLine>& walls, const PolygonSettings& settings,
                                    std::string& why);

double polygon_area(const std::vector<Eigen::Vector2d>& corners);

// Where the lines na . p = oa and nb . p = ob meet (they must not be parallel).
Eigen::Vector2d intersect_lines(const Eigen::Vector2d& na, double oa, const Eigen::Vector2d& nb, double ob);

}  // namespace scanbus::room_measurement
