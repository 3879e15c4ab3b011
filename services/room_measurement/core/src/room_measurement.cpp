#include "scanbus/room_measurement/room_measurement.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <tuple>

namespace scanbus::room_measurement {

namespace {

// Corner-to-corner lengths and their one-sigma uncertainty from the offsets' standard
// errors of the wall and its two neighbours (normal directions taken as exact).
void measure_lengths(std::vector<MeasuredWall>& walls) {
  const size_t count = walls.size();
  for (size_t i = 0; i < count; ++i) {
    const WallLine& before = walls[(i + count - 1) % count].line;
    const WallLine& wall = walls[i].line;
    const WallLine& after = walls[(i + 1) % count].line;
    auto length = [&](double d_before, double d_wall, double d_after) {
      const Eigen::Vector2d start =
          intersect_lines(before.normal, before.offset + d_before, wall.normal, wall.offset + d_wall);
      const Eigen::Vector2d end =
          intersect_lines(wall.normal, wall.offset + d_wall, after.normal, after.offset + d_after);
      return (end - start).norm();
    };
    walls[i].length = length(0, 0, 0);
    const double by_before = length(before.offset_sigma, 0, 0) - walls[i].length;
    const double by_wall = length(0, wall.offset_sigma, 0) - walls[i].length;
    const double by_after = length(0, 0, after.offset_sigma) - walls[i].length;
    walls[i].length_sigma = std::sqrt(by_before * by_before + by_wall * by_wall + by_after * by_after);
  }
}

// How far from a wall's line its points are taken: `least`, or `noise_sigmas` of the range
// noise at the point's range where that is wider.
struct Band {
  double least = 0;
  double noise_sigmas = 0, range_noise = 0, range_noise_per_metre = 0;
  double at(double range) const {
    return std::max(least, noise_sigmas * (range_noise + range_noise_per_metre * range));
  }
};

// Points whose rays meet the wall's line within its extent (kept `band.least` from its ends,
// where the neighbouring wall's points come near) and between `z_low` and `z_high`, lying within
// the band of the line. Chosen by where the ray meets the line, not by the point: range noise
// moves a point along its ray, and a cut on the noisy position keeps more short ranges there.
std::vector<Eigen::Vector3f> points_on_wall(const WallLine& wall, const std::vector<Eigen::Vector3f>& points,
                                            const Band& within, double z_low = -1e9, double z_high = 1e9) {
  const double band = within.least;
  std::vector<Eigen::Vector3f> near;
  for (const auto& p : points) {
    const Eigen::Vector2d xy = p.head<2>().cast<double>();
    const double distance = wall.normal.dot(xy);
    if (std::abs(distance - wall.offset) >= within.at(p.norm())) continue;
    const Eigen::Vector3d crossing = wall.on_ray(p.cast<double>());
    const double along = wall.direction().dot(crossing.head<2>());
    if (along > wall.start + band && along < wall.end - band && crossing.z() >= z_low && crossing.z() <= z_high)
      near.push_back(p);
  }
  return near;
}

// The walls, corners, lengths and area fitted together with the device's errors.
void adjust(const AdjustmentSettings& settings, const std::vector<Eigen::Vector3f>& points, RoomResult& result) {
  // The walls' points within the adjustment's band, without those near the floor and
  // the ceiling: they lie on other planes and would pull the device terms (a wall's plane is
  // the model). Without a floor or ceiling, 10 cm of the wall's own height range goes at that end.
  // A wall's points lie between its corners, and those of every wall refined from the same
  // candidate line: one wall of the room broken by a chimney breast or a T's stem standing in
  // front of it. Not along the candidate's whole extent: across the gap between its pieces the
  // breast's or the stem's sides cross the line, and their points bent the device terms (a
  // 2.6 cm range bias fitted to a T room scanned by an ideal device).
  const size_t count = result.walls.size();
  std::vector<std::pair<double, double>> segments;
  for (size_t i = 0; i < count; ++i) {
    const WallLine& line = result.walls[i].line;
    const double from = line.direction().dot(result.corners[i]);
    const double to = line.direction().dot(result.corners[(i + 1) % count]);
    segments.emplace_back(std::max(line.start, std::min(from, to)), std::min(line.end, std::max(from, to)));
  }
  const Band band{settings.band, settings.band_noise_sigmas, settings.range_noise, settings.range_noise_per_metre};
  std::vector<WallLine> lines;
  for (size_t i = 0; i < count; ++i) {
    WallLine line = result.walls[i].line;
    line.inliers.clear();
    for (size_t j = 0; j < count && !line.inferred; ++j) {
      if (result.walls[j].candidate != result.walls[i].candidate) continue;
      WallLine piece = line;
      std::tie(piece.start, piece.end) = segments[j];
      const auto near = points_on_wall(piece, points, band, result.floor_z.value_or(line.z_low) + 0.1,
                                       result.ceiling_z.value_or(line.z_high) - 0.1);
      line.inliers.insert(line.inliers.end(), near.begin(), near.end());
    }
    lines.push_back(std::move(line));
  }
  const AdjustedWalls adjusted = adjust_walls(lines, settings);
  for (size_t i = 0; i < count; ++i) {
    result.walls[i].line.normal = adjusted.normals[i];
    result.walls[i].line.offset = adjusted.offsets[i];
    result.walls[i].length = adjusted.lengths[i];
    result.walls[i].length_sigma = adjusted.length_sigmas[i];
  }
  result.corners = adjusted.corners;
  result.corner_sigmas = adjusted.corner_sigmas;
  result.area = adjusted.area;
  result.area_sigma = adjusted.area_sigma;
  if (settings.estimate_device) {
    using State = DeviceEstimate::State;
    result.device = {adjusted.device_held ? State::Held : State::Applied,
                     adjusted.range_bias,
                     adjusted.lever_arm,
                     adjusted.pitch_offset,
                     adjusted.yaw_error.norm(),
                     adjusted.unit_information,
                     adjusted.unit_rhs,
                     adjusted.unit_step_leaks};
  }
}

// The floor is a horizontal plane among the lowest points, the ceiling among the highest:
// one RANSAC plane in a band at each end of the height range (tables, beds and sofa tops
// stand higher than the floor's band, and hold more points than the floor can from a
// scanner that looks at most 30 degrees down). Heights are the inliers' medians: a plane
// tilted within the eps angle is off at the origin.
struct Horizontals {
  std::vector<Eigen::Vector2f> floor, ceiling;  // the planes' inliers, x-y
};

Horizontals find_floor_and_ceiling(const std::vector<Eigen::Vector3f>& points, const RoomSettings& settings,
                                   RoomResult& result) {
  Horizontals found;
  std::vector<float> heights;
  const size_t stride = std::max<size_t>(1, points.size() / settings.max_horizontal_samples);
  for (size_t i = 0; i < points.size(); i += stride) heights.push_back(points[i].z());
  std::sort(heights.begin(), heights.end());
  const float low = heights[heights.size() / 100], high = heights[heights.size() * 99 / 100];
  RansacSettings ransac = settings.ransac;
  ransac.max_planes = 1;
  auto plane_height = [&](float from, float to, std::vector<Eigen::Vector2f>& xy) -> std::optional<double> {
    std::vector<Eigen::Vector3f> band;
    for (size_t i = 0; i < points.size(); i += stride)
      if (points[i].z() >= from && points[i].z() <= to) band.push_back(points[i]);
    const auto planes = extract_planes(band, false, ransac);
    if (planes.empty()) return std::nullopt;
    std::vector<float> z;
    for (const auto& p : planes.front().inliers) z.push_back(p.z()), xy.push_back(p.head<2>());
    std::nth_element(z.begin(), z.begin() + static_cast<long>(z.size() / 2), z.end());
    return z[z.size() / 2];
  };
  constexpr float kBand = 0.3f;  // m
  if (low < 0) result.floor_z = plane_height(low - kBand, low + kBand, found.floor);
  if (high > 0) result.ceiling_z = plane_height(high - kBand, high + kBand, found.ceiling);
  if (result.floor_z && *result.floor_z >= 0) result.floor_z.reset();
  if (result.ceiling_z && *result.ceiling_z <= 0) result.ceiling_z.reset();
  return found;
}

// Share of points at least `margin` inside the room's outline.
double share_inside(const std::vector<Eigen::Vector2f>& points, const std::vector<Eigen::Vector2d>& corners,
                    double margin) {
  if (points.empty()) return 0;
  size_t inside = 0;
  for (const auto& p : points) {
    const Eigen::Vector2d q = p.cast<double>();
    bool in = false;  // even-odd rule, then clear of every wall by the margin
    double nearest = 1e9;
    for (size_t i = 0, j = corners.size() - 1; i < corners.size(); j = i++) {
      const Eigen::Vector2d &a = corners[i], &b = corners[j];
      if ((a.y() > q.y()) != (b.y() > q.y()) && q.x() < (b.x() - a.x()) * (q.y() - a.y()) / (b.y() - a.y()) + a.x())
        in = !in;
      const double s = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      nearest = std::min(nearest, (q - (a + s * (b - a))).norm());
    }
    inside += in && nearest >= margin;
  }
  return static_cast<double>(inside) / points.size();
}

// Without the room's outline the floor and ceiling cannot be checked: no height then.
void drop_unchecked_heights(RoomResult& result) {
  result.floor_z.reset();
  result.ceiling_z.reset();
  result.height_note = "not measured: floor and ceiling are checked against the room's outline, which did not close";
}

// A floor or ceiling counts only where it is seen: a plane whose points hug the walls is the
// walls' lowest (or highest) points from a scanner that cannot see the floor (a ring, in a
// closet), and one with walls reaching past it is a table, a bed or a shelf. Then no
// ceiling height, and `height_note` says why.
void check_floor_and_ceiling(const Horizontals& found, RoomResult& result) {
  constexpr double kInside = 0.15, kMinShare = 0.3, kPast = 0.1;  // m, share, m
  double wall_low = 1e9, wall_high = -1e9;
  for (const auto& wall : result.walls)
    wall_low = std::min(wall_low, wall.line.z_low), wall_high = std::max(wall_high, wall.line.z_high);
  auto check = [&](std::optional<double>& z, const std::vector<Eigen::Vector2f>& xy, bool floor) {
    const char* name = floor ? "floor" : "ceiling";
    if (!z) {
      result.height_note = std::string(name) + " not found";
      return;
    }
    if (share_inside(xy, result.corners, kInside) < kMinShare) {
      result.height_note = std::string(name) + " not in view: its plane is the walls' " +
                           (floor ? "lowest" : "highest") + " points, not a surface seen inside the room";
      z.reset();
    } else if (floor ? wall_low < *z - kPast : wall_high > *z + kPast) {
      result.height_note = std::string(name) + " not in view: walls reach " + (floor ? "below" : "above") +
                           " the plane found (furniture), not the " + name;
      z.reset();
    }
  };
  check(result.floor_z, found.floor, true);
  check(result.ceiling_z, found.ceiling, false);
}

// The highest surface the scanner sees (the ceiling, else the cloud's top) and its steepest
// upward ray, from the cloud itself.
ViewLimits view_limits(const std::vector<Eigen::Vector3f>& points, const RoomResult& result) {
  ViewLimits view;
  std::vector<float> heights;
  const size_t stride = std::max<size_t>(1, points.size() / 50000);
  double steepest = 0;
  for (size_t i = 0; i < points.size(); i += stride) {
    heights.push_back(points[i].z());
    const double horizontal = points[i].head<2>().norm();
    if (horizontal > 0.3) steepest = std::max(steepest, points[i].z() / horizontal);
  }
  const size_t top = heights.size() * 999 / 1000;  // past a few outliers
  std::nth_element(heights.begin(), heights.begin() + static_cast<long>(top), heights.end());
  view.top = result.ceiling_z.value_or(heights[top]);
  view.tan_elevation = std::max(steepest, 0.05);
  return view;
}

// The profile runs on past a wall's inliers' ends as far as the wall above a wardrobe in a
// corner may lie (a wide wardrobe is 2 m): enclosing_runs counts it there behind furniture.
constexpr double kProfileMargin = 2.0;  // m

// Each wall's profile along its line and how much of it the scanner sees over, from every valid point.
void describe_walls(std::vector<WallLine>& walls, const RoomSettings& settings,
                    const std::vector<Eigen::Vector3f>& valid, const ViewLimits& view) {
  const PolygonSettings& p = settings.polygon;
  for (auto& wall : walls) {
    wall.profile = wall_profile(wall, valid, settings.ransac.distance, settings.opening_beyond, kProfileMargin);
    wall.seen_over = seen_over_share(wall, valid, 0.1, 0.2, view.top_at(wall.offset) - p.top_margin - p.top_band);
  }
}

// The vertical planes among `points` that hold min_plane_share of them and pass the wall tests
// (height, its coverage, fill along the line), merged where RANSAC split one wall, described.
std::vector<WallLine> wall_candidates(const std::vector<Eigen::Vector3f>& points, const RoomSettings& settings,
                                      const std::vector<Eigen::Vector3f>& valid, const ViewLimits& view) {
  RansacSettings vertical = settings.ransac;  // planes holding less of the points are clutter
  vertical.min_inliers = std::max(vertical.min_inliers, static_cast<size_t>(settings.min_plane_share * points.size()));
  constexpr double kRunGap = 1.0, kMinRun = 0.25;  // m: the narrowest opening; shorter than the shortest
                                                   // chimney-breast side, longer than a crossing wall's band
  std::vector<WallLine> walls;
  for (Plane& plane : extract_planes(points, true, vertical)) {
    WallLine wall = fit_wall(std::move(plane.inliers));
    auto runs = long_runs(wall, kRunGap, kMinRun);
    if (runs.size() < vertical.min_inliers) continue;
    if (runs.size() < wall.inliers.size()) wall = fit_wall(std::move(runs));
    if (wall.z_high - wall.z_low >= settings.min_wall_height && wall.z_coverage >= settings.min_wall_coverage &&
        wall.z_gap <= settings.max_wall_height_gap && wall.length_coverage >= settings.min_wall_fill)
      walls.push_back(std::move(wall));
  }
  walls = merge_collinear(std::move(walls), 3 * M_PI / 180, settings.ransac.distance / 2, 3 * settings.ransac.distance);
  describe_walls(walls, settings, valid, view);
  return walls;
}

// The points whose direction from the scanner lies in the sector, away from the floor and the
// ceiling: in a sector, their scan lines run out radially and make vertical planes with the
// columns they meet.
std::vector<Eigen::Vector3f> in_sector(const std::vector<Eigen::Vector3f>& points, const Sector& sector,
                                       const RoomResult& result) {
  constexpr double kBand = 0.15;  // m off the floor and the ceiling
  const double low = result.floor_z.value_or(-1e9) + kBand, high = result.ceiling_z.value_or(1e9) - kBand;
  std::vector<Eigen::Vector3f> inside;
  for (const auto& p : points) {
    if (p.z() <= low || p.z() >= high) continue;
    double angle = std::atan2(p.y(), p.x());
    while (angle < sector.first) angle += 2 * M_PI;
    if (angle <= sector.last) inside.push_back(p);
  }
  return inside;
}

// Whether the scanner sees the wall face on enough to be one it looks at across an open sector:
// rays meeting it within kGrazing of its plane are columns of other surfaces lined up radially.
bool faces_scanner(const WallLine& wall) {
  constexpr double kGrazing = 10 * M_PI / 180;
  std::vector<double> sines;
  for (const auto& p : wall.inliers)
    sines.push_back(wall.offset / std::max(1e-6, static_cast<double>(p.head<2>().norm())));
  std::nth_element(sines.begin(), sines.begin() + static_cast<long>(sines.size() / 2), sines.end());
  return !sines.empty() && sines[sines.size() / 2] >= std::sin(kGrazing);
}

// The side joining each step between parallel walls (step_gaps), looked for among the gap's
// own points: of the planes there that face the scanner and join the step, the one with the
// most inliers (the rest are the gap's edges lined up with clutter).
std::vector<WallLine> step_sides(const std::vector<WallLine>& candidates, const std::vector<Eigen::Vector3f>& points,
                                 const RoomSettings& settings, const std::vector<Eigen::Vector3f>& valid,
                                 const ViewLimits& view, const RoomResult& result) {
  constexpr double kMargin = 2;   // degrees either side of the gap: the side's ends
  constexpr double kReach = 0.3;  // m: the side meets the step's walls this near where the turn leaves or meets them
  std::vector<WallLine> sides;
  for (const Step& step : step_gaps(candidates, view, settings.polygon, kMargin)) {
    std::optional<WallLine> best;
    for (WallLine& wall : wall_candidates(in_sector(points, step.sector, result), settings, valid, view))
      if (faces_scanner(wall) && joins_step(wall, candidates, step, kReach) &&
          (!best || wall.inliers.size() > best->inliers.size()))
        best = std::move(wall);
    if (!best) continue;
    best->step_side = true;
    sides.push_back(std::move(*best));
  }
  return sides;
}

// The final fit of a room wall: every valid point on it (points_on_wall), fitted again, twice.
// RANSAC's inliers are voxel centres cut off at its distance threshold; the histogram filter's
// points are no better: a point that range noise carried behind the wall lands in a sparse
// bin the filter drops, so its survivors sit in front (rooms came out 1-2 cm small).
WallLine refine_wall(const WallLine& wall, const std::vector<Eigen::Vector3f>& points, double band) {
  // A refit turned further than this from the candidate's line is not the same wall: rays that
  // graze a short wall (a step's side seen nearly edge on) meet its line anywhere, and the
  // points chosen by where they meet it scatter. The last fit that did not turn stands.
  const double max_turn = std::cos(5 * M_PI / 180);
  WallLine fitted = wall;
  for (int round = 0; round < 2; ++round) {
    std::vector<Eigen::Vector3f> near = points_on_wall(fitted, points, Band{band});
    if (near.size() < 10) break;
    const WallLine refit = fit_wall(std::move(near));
    if (std::abs(refit.normal.dot(wall.normal)) < max_turn) break;
    fitted.normal = refit.normal;
    fitted.offset = refit.offset;
    fitted.rms = refit.rms;
    fitted.offset_sigma = refit.offset_sigma;
    fitted.inliers = refit.inliers;
  }
  return fitted;
}

// Each inferred wall placed again from its refined neighbours: through the nearer one's end
// (the corner the scanner saw), with that end's uncertainty (the sampling step there and half
// the beam's footprint) as its offset's sigma; its other corner is inferred.
void place_hidden_walls(const std::vector<Eigen::Vector3f>& points, const RoomSettings& settings, RoomResult& result) {
  constexpr double kMaxGap = 0.15;  // m: a wider gap in a wall's points is not its body
  const size_t count = result.walls.size();
  result.corner_inferred.assign(count, false);
  for (size_t i = 0; i < count; ++i) {
    if (!result.walls[i].inferred()) continue;
    const WallLine& before = result.walls[(i + count - 1) % count].line;
    const WallLine& after = result.walls[(i + 1) % count].line;
    const bool before_nearer = before.offset < after.offset;
    const WallLine& nearer = before_nearer ? before : after;
    // Its height over furniture and under the ceiling: the floor's and the ceiling's points run on
    // past the corner, and so may a desk or a sideboard standing on from under its end.
    constexpr double kFurniture = 1.1;  // m over its lowest points: desks, sideboards and counters stand lower
    const double low = std::min(nearer.z_low + kFurniture, (nearer.z_low + nearer.z_high) / 2);
    std::vector<Eigen::Vector3f> body;
    for (const auto& p : points)
      if (p.z() > low && p.z() < nearer.z_high - 0.2) body.push_back(p);
    const Eigen::Vector2d placed =
        intersect_lines(nearer.normal, nearer.offset, result.walls[i].line.normal, result.walls[i].line.offset);
    const WallEnd end =
        wall_end(nearer, nearer.direction().dot(placed), before_nearer, body, 2 * settings.ransac.distance, kMaxGap);
    const Eigen::Vector2d corner = nearer.offset * nearer.normal + end.along * nearer.direction();
    const double footprint = corner.norm() * settings.beam_divergence / 2;
    WallLine hidden = infer_hidden_wall(before, after, end.along);
    hidden.offset_sigma = std::hypot(end.spacing / std::sqrt(12.0), footprint);  // a uniform shortfall's sigma
    result.walls[i].line = hidden;
    result.corner_inferred[before_nearer ? (i + 1) % count : i] = true;
  }
}

// An outline measured and then found not to close: no walls, corners or area, and why.
void refuse_outline(std::string why, RoomResult& result) {
  result.status = RoomStatus::WallsDoNotClose;
  result.message = std::move(why);
  result.walls.clear();
  result.corners.clear();
  result.corner_inferred.clear();
  result.corner_sigmas.clear();
  result.area = result.area_sigma = 0;
  drop_unchecked_heights(result);
}

// Whether a final wall has points on its line well past its corner with `neighbour` (beyond
// the scatter the corner leaves, off the neighbour's line: at a shallow corner that runs close
// to this one's): it goes on behind the neighbour's end (the wall behind a chimney breast's
// hidden side, seen just past where the breast's front meets its line), so the corner is not
// one. room_polygon checked the candidates only at one place past (from 0.25 m), with their
// profiles. Heights over furniture (a desk may stand on past a pillar's corner).
bool runs_past_corner(const std::vector<Eigen::Vector3f>& points, const WallLine& wall, const WallLine& neighbour,
                      const Eigen::Vector2d& corner, int direction) {
  constexpr double kBand = 0.04, kFrom = 0.1, kStretch = 0.3;  // m: band about the lines, stretch past the corner
  constexpr double kFurniture = 1.1, kCeiling = 0.2;           // m over its lowest, under its highest points
  constexpr size_t kMinPoints = 10;
  if (wall.inferred) return false;
  const double at = wall.direction().dot(corner);
  const double from = std::max(kFrom, clear_of_neighbour(wall, neighbour));
  size_t past = 0;
  for (const auto& p : points) {
    const Eigen::Vector2d xy = p.head<2>().cast<double>();
    if (std::abs(wall.normal.dot(xy) - wall.offset) > kBand || p.z() < wall.z_low + kFurniture ||
        p.z() > wall.z_high - kCeiling || std::abs(neighbour.normal.dot(xy) - neighbour.offset) <= kBand)
      continue;
    const double beyond = direction * (wall.direction().dot(xy) - at);
    past += beyond > from && beyond < from + kStretch;
  }
  return past >= kMinPoints;
}

bool refuse_hidden_corner(const std::vector<Eigen::Vector3f>& points, RoomResult& result) {
  const size_t count = result.walls.size();
  for (size_t i = 0; i < count; ++i) {
    const size_t before = (i + count - 1) % count;
    const WallLine& a = result.walls[before].line;
    const WallLine& b = result.walls[i].line;
    const bool before_runs = runs_past_corner(points, a, b, result.corners[i], +1);
    if (!before_runs && !runs_past_corner(points, b, a, result.corners[i], -1)) continue;
    const size_t runs = before_runs ? before : i, other = before_runs ? i : before;
    refuse_outline("wall " + std::to_string(runs + 1) + " is seen on past its corner with wall " +
                       std::to_string(other + 1) + ": a wall between them is hidden, the walls do not close a room",
                   result);
    return true;
  }
  return false;
}

// Where a ray from the scanner (the origin) first crosses a closed outline: the wall
// (corners[wall] to the next corner), how far along it as a share, how far along the ray.
struct OutlineCrossing {
  size_t wall = 0;
  double share = 0, range = std::numeric_limits<double>::max();
};

std::optional<OutlineCrossing> first_crossing(const std::vector<Eigen::Vector2d>& corners,
                                              const std::vector<Eigen::Vector2d>& edges, const Eigen::Vector2d& ray) {
  std::optional<OutlineCrossing> first;
  for (size_t i = 0; i < corners.size(); ++i) {
    const double denominator = cross(ray, edges[i]);
    if (std::abs(denominator) < 1e-12) continue;
    const double range = cross(corners[i], edges[i]) / denominator, share = cross(corners[i], ray) / denominator;
    if (range > 0 && share >= 0 && share <= 1 && (!first || range < first->range)) first = {i, share, range};
  }
  return first;
}

// Whether a wall is seen on past a convex corner of the closed outline, behind its neighbour's
// line: the outline cuts off part of the room. A built-in cupboard's or a boxed-in stair's
// front near a corner closes on the side wall as an L's inner wall would (its side towards the
// corner and the gap behind it out of view); only the side wall, seen through the gap's mouth
// past the front's end, tells the two apart. Each valid return's ray in the plane is followed to
// where it leaves the outline. It counts for the nearer corner of the wall it leaves through
// when it lies beyond the crossing by more than max(kAlong, 4 range-noise sigmas) along the ray
// and kAcross to recess_depth past the wall's line (at grazing incidence an angle error moves a
// point far along its ray, not across the line; a corridor behind a door the openings missed
// lies farther), on the line of the corner's other wall (a set-back door or a step in a wall
// lies parallel to the wall instead), not through an opening and at the wall's heights. The
// count needed grows with the cloud's density, as the histogram filter's does.
bool refuse_returns_beyond(const std::vector<Eigen::Vector3f>& points, const RoomSettings& settings,
                           RoomResult& result) {
  constexpr double kAlong = 0.15, kAcross = 0.05, kSigmas = 4;  // m, m
  constexpr double kOpeningMargin = 0.1, kWallHeights = 0.3;    // m along the wall, m inside its heights
  constexpr double kMinReturns = 8;                             // in a scan of density_reference points
  const auto& corners = result.corners;
  const size_t count = corners.size();
  std::vector<Eigen::Vector2d> edges(count);
  for (size_t i = 0; i < count; ++i) edges[i] = corners[(i + 1) % count] - corners[i];
  const double sense = signed_area(corners);  // rays leave where they cross an edge along it
  const auto& a = settings.adjustment;
  const Band past_crossing{kAlong, kSigmas, a.range_noise, a.range_noise_per_metre};
  const Band on_other_wall{settings.ransac.distance, 3, a.range_noise, a.range_noise_per_metre};
  // Per wall and end (2 i: its start, corners[i]; 2 i + 1: its end), the returns beyond it there.
  std::vector<size_t> beyond(2 * count, 0);
  for (const auto& p : points) {
    const Eigen::Vector2d xy = p.head<2>().cast<double>();
    const double range = xy.norm();
    if (range < 1e-6) continue;
    const Eigen::Vector2d ray = xy / range;
    const auto crossing = first_crossing(corners, edges, ray);
    // None, or a ray entering the outline (a scanner outside it): nothing is beyond.
    if (!crossing || sense * cross(ray, edges[crossing->wall]) <= 0) continue;
    const size_t i = crossing->wall;
    const MeasuredWall& wall = result.walls[i];
    if (wall.inferred() || p.z() < wall.line.z_low + kWallHeights || p.z() > wall.line.z_high - kWallHeights) continue;
    const double across = wall.line.normal.dot(xy) - wall.line.offset;
    if (range - crossing->range < past_crossing.at(range) || across < kAcross || across >= settings.recess_depth)
      continue;
    const bool at_end = crossing->share >= 0.5;
    const Eigen::Vector2d& before = edges[at_end ? i : (i + count - 1) % count];
    const Eigen::Vector2d& after = edges[at_end ? (i + 1) % count : i];
    const WallLine& other = result.walls[at_end ? (i + 1) % count : (i + count - 1) % count].line;
    if (sense * cross(before, after) <= 0 ||  // a reflex corner: its other wall runs on into the room
        std::abs(other.normal.dot(xy) - other.offset) > on_other_wall.at(range))
      continue;
    const double along = crossing->share * edges[i].norm();
    const bool in_opening = std::any_of(wall.openings.begin(), wall.openings.end(), [&](const Opening& o) {
      return along > o.start - kOpeningMargin && along < o.start + o.width + kOpeningMargin;
    });
    beyond[2 * i + at_end] += !in_opening;
  }
  const double density =
      std::max(1.0, static_cast<double>(points.size()) / std::max<size_t>(1, settings.density_reference));
  for (size_t end = 0; end < beyond.size(); ++end) {
    if (static_cast<double>(beyond[end]) < kMinReturns * density) continue;
    const size_t wall = end / 2, runs_on = end % 2 ? (wall + 1) % count : (wall + count - 1) % count;
    refuse_outline("wall " + std::to_string(runs_on + 1) + " is seen on past its corner with wall " +
                       std::to_string(wall + 1) + ", behind that wall's line (" + std::to_string(beyond[end]) +
                       " returns): the outline cuts off part of the room (a side or a recess out of view), "
                       "the walls do not close it",
                   result);
    return true;
  }
  return false;
}

// A surface seen through an opening shallower than `recess_depth` behind it is the back of a
// recess (an alcove, a bay) whose sides were not found as walls: the outline would cut it off,
// so the room is refused, saying where. Corridors behind doors are deeper.
bool refuse_recess(double recess_depth, RoomResult& result) {
  for (size_t i = 0; i < result.walls.size(); ++i)
    for (const auto& opening : result.walls[i].openings) {
      if (opening.depth <= 0 || opening.depth >= recess_depth) continue;
      char what[200];
      std::snprintf(what, sizeof what, "wall %zu has a recess %.2f m wide and %.2f m deep at %.2f m along it", i + 1,
                    opening.width, opening.depth, opening.start);
      refuse_outline(
          std::string(what) + " (an alcove or a bay whose sides are not found as walls): the outline would cut it off",
          result);
      return true;
    }
  return false;
}

void error_histogram(const std::vector<Eigen::Vector3f>& points, RoomResult& result) {
  if (result.walls.empty()) return;
  const auto longest = std::max_element(result.walls.begin(), result.walls.end(),
                                        [](const auto& a, const auto& b) { return a.length < b.length; });
  const WallLine& wall = longest->line;
  result.error_histogram.assign(static_cast<size_t>(0.10 / result.error_bin), 0);
  for (const auto& p : points) {
    const Eigen::Vector2d xy = p.head<2>().cast<double>();
    const double distance = std::abs(wall.normal.dot(xy) - wall.offset);
    const double along = wall.direction().dot(xy);
    if (distance >= 0.10 || along < wall.start || along > wall.end) continue;
    ++result.error_histogram[static_cast<size_t>(distance / result.error_bin)];
  }
}

RoomResult measure(const std::vector<Eigen::Vector3f>& input, const RoomSettings& settings) {
  RoomResult result;
  result.points_in = input.size();
  std::vector<Eigen::Vector3f> valid;
  valid.reserve(input.size());
  for (const auto& p : input)
    if (p.allFinite()) valid.push_back(p);
  result.points_valid = valid.size();
  if (valid.size() < settings.ransac.min_inliers * 3) {
    result.status = RoomStatus::TooFewPoints;
    result.message = std::to_string(valid.size()) + " valid points: too few to find walls";
    return result;
  }
  const Horizontals horizontals = find_floor_and_ceiling(valid, settings, result);

  // The thesis's density threshold is for its ~18,560-point scans: denser clouds scale it.
  HistogramFilterSettings histogram = settings.histogram;
  if (settings.density_reference > 0 && valid.size() > settings.density_reference)
    histogram.min_points = static_cast<int>(histogram.min_points * valid.size() / settings.density_reference);
  const std::vector<Eigen::Vector3f> filtered = histogram_filter(valid, histogram);
  result.points_after_filter = filtered.size();
  std::vector<Eigen::Vector3f> walls_only = filtered;
  if (settings.voxel_leaf > 0) {
    VoxelResult voxels = voxel_grid(filtered, settings.voxel_leaf);
    result.voxel_overflow = voxels.overflow;
    walls_only = std::move(voxels.points);
  }
  result.points_after_voxel = walls_only.size();

  const ViewLimits view = view_limits(valid, result);
  std::vector<WallLine> candidates = wall_candidates(walls_only, settings, valid, view);
  // A wall with few returns (far, or glass) makes no plane of the whole cloud's share: where no
  // wall encloses the scanner, the planes are looked for again among that sector's points alone.
  std::vector<WallLine> sector_walls;
  for (const Sector& sector : open_sectors(candidates, view, settings.polygon, settings.open_sector_deg))
    for (WallLine& wall : wall_candidates(in_sector(walls_only, sector, result), settings, valid, view))
      if (faces_scanner(wall)) sector_walls.push_back(std::move(wall));
  // So may the short side of a step between parallel walls.
  for (WallLine& side : step_sides(candidates, walls_only, settings, valid, view, result))
    sector_walls.push_back(std::move(side));
  if (!sector_walls.empty()) {
    candidates.insert(candidates.end(), sector_walls.begin(), sector_walls.end());
    candidates = merge_collinear(std::move(candidates), 3 * M_PI / 180, settings.ransac.distance / 2,
                                 3 * settings.ransac.distance);
    describe_walls(candidates, settings, valid, view);
  }
  result.candidates = candidates;
  if (candidates.size() < 3) {
    result.status = RoomStatus::TooFewWalls;
    result.message = "found " + std::to_string(candidates.size()) + " wall planes, a room needs at least 3";
    drop_unchecked_heights(result);
    return result;
  }
  std::string why;
  const std::optional<Polygon> polygon = room_polygon(candidates, view, settings.polygon, why);
  if (!polygon) {
    result.status = RoomStatus::WallsDoNotClose;
    result.message = why;
    drop_unchecked_heights(result);
    return result;
  }
  for (size_t index : polygon->walls) {
    const WallLine& candidate = candidates[index];
    MeasuredWall wall;
    wall.line = candidate.inferred ? candidate : refine_wall(candidate, valid, 2 * settings.ransac.distance);
    wall.points = wall.line.inliers.size();
    wall.candidate = index;
    result.walls.push_back(std::move(wall));
  }
  place_hidden_walls(valid, settings, result);
  const size_t count = result.walls.size();
  for (size_t i = 0; i < count; ++i) {  // corners of the refined walls
    const WallLine& before = result.walls[(i + count - 1) % count].line;
    const WallLine& wall = result.walls[i].line;
    result.corners.push_back(intersect_lines(before.normal, before.offset, wall.normal, wall.offset));
  }
  if (settings.adjustment.enabled) {
    adjust(settings.adjustment, valid, result);  // lengths, sigmas, corners and area
  } else {
    measure_lengths(result.walls);
    result.area = polygon_area(result.corners);
  }
  if (refuse_hidden_corner(valid, result)) return result;
  check_floor_and_ceiling(horizontals, result);
  for (size_t i = 0; i < count; ++i)
    if (!result.walls[i].inferred())  // a wall turned away from the scanner: nothing is seen through it
      result.walls[i].openings =
          find_openings(result.walls[i].line, result.corners[i], result.corners[(i + 1) % count], valid,
                        settings.ransac.distance, settings.opening_beyond, settings.opening_min_width);
  if (refuse_recess(settings.recess_depth, result)) return result;
  if (refuse_returns_beyond(valid, settings, result)) return result;
  for (const auto& wall : result.walls) result.perimeter += wall.length;
  error_histogram(valid, result);
  const auto hidden =
      std::count_if(result.walls.begin(), result.walls.end(), [](const auto& w) { return w.inferred(); });
  result.message = std::to_string(result.walls.size()) + " walls";
  if (hidden > 0)
    result.message += ", " + std::to_string(hidden) +
                      " of them not seen but inferred (perpendicular between the parallel walls they join)";
  if (result.voxel_overflow) result.message += "; VoxelGrid skipped: the cloud spans too far for 32-bit voxel indices";
  return result;
}

}  // namespace

const char* status_name(RoomStatus status) {
  switch (status) {
    case RoomStatus::Ok:
      return "ok";
    case RoomStatus::TooFewPoints:
      return "too_few_points";
    case RoomStatus::TooFewWalls:
      return "too_few_walls";
    case RoomStatus::WallsDoNotClose:
      return "walls_do_not_close";
    case RoomStatus::InputError:
      return "input_error";
  }
  return "unknown";
}

const char* device_state_name(DeviceEstimate::State state) {
  switch (state) {
    case DeviceEstimate::State::NotEstimated:
      return "not_estimated";
    case DeviceEstimate::State::Applied:
      return "applied";
    case DeviceEstimate::State::Held:
      return "held";
  }
  return "unknown";
}

RoomResult measure_room(const std::vector<Eigen::Vector3f>& points, const RoomSettings& settings) {
  const auto started = std::chrono::steady_clock::now();
  RoomResult result = measure(points, settings);
  result.elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return result;
}

RoomSettings room_settings_from_config(const Config& section) {
  RoomSettings s;
  const Config histogram = section.section("histogram");
  s.histogram.bins = static_cast<int>(histogram.integer("bins", s.histogram.bins, 1, 10000));
  s.histogram.min_range = histogram.number("min_range", s.histogram.min_range, 0, 100);
  s.histogram.min_points = static_cast<int>(histogram.integer("min_points", s.histogram.min_points, 1, 1000000));
  s.histogram.min_z_spread = histogram.number("min_z_spread", s.histogram.min_z_spread, 0, 100);
  s.histogram.reference_range = histogram.number("reference_range", s.histogram.reference_range, 0.1, 100);
  s.voxel_leaf = section.number("voxel_leaf", s.voxel_leaf, 0, 10);
  s.density_reference = static_cast<size_t>(section.integer("density_reference", 18560, 0, 1000000000));
  const Config ransac = section.section("ransac");
  s.ransac.distance = ransac.number("distance", s.ransac.distance, 0.001, 1);
  s.ransac.eps_angle_deg = ransac.number("eps_angle", s.ransac.eps_angle_deg, 0.01, 45);
  s.ransac.iterations = static_cast<int>(ransac.integer("iterations", s.ransac.iterations, 1, 1000000));
  s.ransac.min_inliers = static_cast<size_t>(ransac.integer("min_inliers", 50, 3, 10000000));
  s.ransac.max_planes = static_cast<int>(ransac.integer("max_planes", s.ransac.max_planes, 1, 1000));
  s.min_plane_share = section.number("min_plane_share", s.min_plane_share, 0, 1);
  s.min_wall_height = section.number("min_wall_height", s.min_wall_height, 0, 100);
  s.min_wall_coverage = section.number("min_wall_coverage", s.min_wall_coverage, 0, 1);
  s.max_wall_height_gap = section.number("max_wall_height_gap", s.max_wall_height_gap, 0, 100);
  s.open_sector_deg = section.number("open_sector", s.open_sector_deg, 0.5, 360);
  s.min_wall_fill = section.number("min_wall_fill", s.min_wall_fill, 0, 1);
  const Config polygon = section.section("polygon");
  // Not under 10 degrees: there insert_hidden_walls takes neighbours for parallel.
  s.polygon.min_wall_angle_deg = polygon.number("min_wall_angle", s.polygon.min_wall_angle_deg, 10, 89);
  s.polygon.min_run_deg = polygon.number("min_run", s.polygon.min_run_deg, 0, 90);
  s.polygon.max_gap_deg = polygon.number("max_gap", s.polygon.max_gap_deg, 0, 180);
  s.polygon.corner_margin = polygon.number("corner_margin", s.polygon.corner_margin, 0, 100);
  s.polygon.extent_tolerance = polygon.number("extent_tolerance", s.polygon.extent_tolerance, 0, 10);
  s.polygon.support_reach = polygon.number("support_reach", s.polygon.support_reach, 0.01, 10);
  s.polygon.top_margin = polygon.number("top_margin", s.polygon.top_margin, 0, 10);
  s.polygon.top_band = polygon.number("top_band", s.polygon.top_band, 0.01, 10);
  s.polygon.max_door_width = polygon.number("max_door_width", s.polygon.max_door_width, 0, 100);
  s.polygon.max_seen_over = polygon.number("max_seen_over", s.polygon.max_seen_over, 0, 1);
  s.polygon.min_hidden_wall = polygon.number("min_hidden_wall", s.polygon.min_hidden_wall, 0.01, 100);
  const Config adjustment = section.section("adjustment");
  s.adjustment.enabled = adjustment.flag("enabled", s.adjustment.enabled);
  s.adjustment.estimate_device = adjustment.flag("estimate_device", s.adjustment.estimate_device);
  s.adjustment.pitch_bin_deg = adjustment.number("pitch_bin", s.adjustment.pitch_bin_deg, 0.01, 90);
  s.adjustment.range_bias_prior = adjustment.number("range_bias_prior", s.adjustment.range_bias_prior, 1e-4, 10);
  s.adjustment.lever_arm_prior = adjustment.number("lever_arm_prior", s.adjustment.lever_arm_prior, 1e-4, 10);
  s.adjustment.pitch_error_prior_deg =
      adjustment.number("pitch_error_prior", s.adjustment.pitch_error_prior_deg, 1e-3, 45);
  s.adjustment.step_error_prior_deg = adjustment.number("step_error_prior", s.adjustment.step_error_prior_deg, 0, 45);
  s.adjustment.band = adjustment.number("band", s.adjustment.band, 0.001, 1);
  s.adjustment.band_noise_sigmas = adjustment.number("band_noise_sigmas", s.adjustment.band_noise_sigmas, 0, 10);
  s.adjustment.range_noise = adjustment.number("range_noise", s.adjustment.range_noise, 0, 1);
  s.adjustment.range_noise_per_metre =
      adjustment.number("range_noise_per_metre", s.adjustment.range_noise_per_metre, 0, 1);
  s.adjustment.yaw_error_prior_deg = adjustment.number("yaw_error_prior", s.adjustment.yaw_error_prior_deg, 1e-3, 45);
  s.adjustment.calibrated_range_bias = adjustment.number("range_bias", s.adjustment.calibrated_range_bias, -1, 1);
  s.adjustment.calibrated_lever_arm = adjustment.number("lever_arm", s.adjustment.calibrated_lever_arm, -1, 1);
  s.adjustment.calibrated_pitch_offset_deg =
      adjustment.number("pitch_offset", s.adjustment.calibrated_pitch_offset_deg, -45, 45);

  s.adjustment.bootstrap = static_cast<int>(adjustment.integer("bootstrap", s.adjustment.bootstrap, 0, 100000));
  s.adjustment.bootstrap_scale = adjustment.number("bootstrap_scale", s.adjustment.bootstrap_scale, 0.5, 3);
  s.opening_min_width = section.number("opening_min_width", s.opening_min_width, 0.01, 100);
  s.recess_depth = section.number("recess_depth", s.recess_depth, 0, 100);
  s.opening_beyond = section.number("opening_beyond", s.opening_beyond, 0.01, 100);
  s.beam_divergence = section.number("beam_divergence", s.beam_divergence, 0, 0.1);
  return s;
}

}  // namespace scanbus::room_measurement
