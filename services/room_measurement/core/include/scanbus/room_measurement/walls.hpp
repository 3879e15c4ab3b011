// Walls as 2D lines fitted to a vertical plane's inliers, and the room's polygon from them.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace scanbus::room_measurement {

// Where along its line a wall has points of the whole cloud (any height, before the
// histogram filter drops short columns such as the wall above a door), and at which heights;
// and where returns beyond it cross its line (it is seen through there: a gap, an opening).
struct WallProfile {
  double origin = 0;              // along-position of slot 0, m
  double slot = 0.05;             // m
  double base = 0, cell = 0.05;   // m: heights in 64 cells from base
  std::vector<uint64_t> cells;    // per slot, a bit for each height cell holding a point
  std::vector<uint64_t> through;  // per slot, a bit for each height cell a return beyond crosses

  // Whether a slot within `reach` of an along-position holds a point (between z_low and z_high).
  bool has_points(double along, double reach, double z_low = -1e9, double z_high = 1e9) const;
  // Whether a return beyond the wall crosses its line there.
  bool seen_through(double along, double reach, double z_low = -1e9, double z_high = 1e9) const;
};

// A vertical wall: normal . (x, y) = offset, normal pointing away from the scanner.
struct WallLine {
  Eigen::Vector2d normal;
  double offset = 0;
  double rms = 0;             // m, inliers' distance to the fitted line
  double offset_sigma = 0;    // m, standard error of the offset
  double start = 0, end = 0;  // extent of the inliers along the wall, m, along (-n.y, n.x)
  double z_low = 0, z_high = 0;
  double z_coverage = 0;       // share of 10 cm height slices between z_low and z_high holding inliers
  double length_coverage = 0;  // share of 10 cm slots between start and end holding inliers
  double z_gap = 0;            // m: the widest band of heights between z_low and z_high with no inlier
  std::vector<Eigen::Vector3f> inliers;
  WallProfile profile;
  bool inferred = false;   // not seen: placed between two parallel walls the scanner saw (infer_hidden_wall)
  bool step_side = false;  // found joining a step between parallel walls (room_measurement's step_sides)
  double seen_over = 0;    // share of its middle where returns pass its line above its top (seen_over_share)

  Eigen::Vector2d direction() const { return {-normal.y(), normal.x()}; }
  // Where the ray from the scanner (the origin) through `point` meets the wall's plane: range
  // noise moves a point along its ray, so this is where it belongs. As an along-position:
  Eigen::Vector3d on_ray(const Eigen::Vector3d& point) const;
  double along_on_ray(const Eigen::Vector2d& point) const;
};

// Least-squares line through the inliers' x-y (total least squares: the smallest
// principal axis is the normal). Extents are robust (1st to 99th percentile).
WallLine fit_wall(std::vector<Eigen::Vector3f> inliers);

// The wall's inliers in runs along its line at least `min_run` long, runs split where no inlier
// lies within `gap`: RANSAC's plane is unbounded, and a wall crossing its line (a corner's
// neighbour) leaves a short run far from the wall's own points, stretching its extent over the
// room (a chimney breast's 1.2 m front then filled a quarter of a 6.7 m extent).
std::vector<Eigen::Vector3f> long_runs(const WallLine& wall, double gap, double min_run);

// Candidates on one line (normals within `angle`, offsets within `same`) are one wall that
// RANSAC split: merged and refitted. A weaker candidate parallel to a stronger one and
// within `tail` of it, or turned a few degrees with its points within `tail` of the stronger
// one's line and length (a sliver through a far wall's noise), is that noise beyond the RANSAC
// band: dropped.
std::vector<WallLine> merge_collinear(std::vector<WallLine> walls, double angle, double same, double tail);

// The wall's profile from every point within `band` of its line, and every point more than
// `beyond` past it, over its extent and `margin` beyond each end. Its heights (base, cell) come
// from the points within 0.5 m of its ends: farther along, its line may cross lower or higher
// ground seen through a door.
WallProfile wall_profile(const WallLine& wall, const std::vector<Eigen::Vector3f>& points, double band, double beyond,
                         double margin);

// Share of the wall's middle (all but `margin` at each end) where returns pass its line more
// than `beyond` past it, crossing it above `z_from`: furniture under the ceiling is seen over
// along all of it (the ceiling behind its top, the wall above it), a wall only through its
// doors, a chimney breast's front nowhere.
double seen_over_share(const WallLine& wall, const std::vector<Eigen::Vector3f>& points, double beyond, double margin,
                       double z_from);

struct Polygon {
  std::vector<size_t> walls;             // indices into the candidates, in order around the room
  std::vector<Eigen::Vector2d> corners;  // corners[i] joins walls[i-1] and walls[i]
};

// The wall the scanner cannot see between two parallel walls that face it one behind the
// other (`before` then `after`, counter-clockwise around the scanner): the side of a chimney
// breast, an alcove or an L's arm, turned away from the scanner. The nearer wall's end on the
// farther one's side is a corner the scanner saw; the hidden wall runs from there
// perpendicular to both (an assumption: it is not seen), so its far corner is inferred.
// `nearer_end` is that end's along-position on the nearer wall.
WallLine infer_hidden_wall(const WallLine& before, const WallLine& after, double nearer_end);

// Whether `before` and `after` are such a pair: parallel within `angle`, facing the same
// way, one at least `min_step` behind the other.
bool hides_a_wall(const WallLine& before, const WallLine& after, double angle, double min_step);

// The along-position where a wall's points end, near `near` (towards its `end` side, else
// its `start`): its points within `band` of its line, followed from a little inside while no
// gap is wider than `max_gap` (a corner's last points), moved on by half the sampling step
// there (the last sample falls short of the end by up to a step), and that step.
struct WallEnd {
  double along = 0, spacing = 0;  // m
};
WallEnd wall_end(const WallLine& wall, double near, bool at_end, const std::vector<Eigen::Vector3f>& points,
                 double band, double max_gap);

struct PolygonSettings {
  double min_wall_angle_deg = 10;  // neighbours closer to parallel than this cannot meet in a corner (a cut
                                   // corner turns 15-45 degrees; under 10 a corner moves along the walls
                                   // 6 times their offset error)
  double min_run_deg = 2;          // a wall seen over less of the turn is clutter
  double max_gap_deg = 40;         // a wider sector with no wall is an open side, not a doorway: no room
  double corner_margin = 1.0;      // m around the points where corners may lie (Algorithm 2)
  double extent_tolerance = 0.05;  // m: rays just past a wall's inlier extent still hit it
  double support_reach = 0.10;     // m: a ray meets a wall only where the wall has points this near
  double top_margin = 0.12;        // m: a wall has points just below the highest surface the scanner
                                   // sees there (from top - top_margin - top_band to top - top_margin;
                                   // not at the top, where the ceiling's own points lie); furniture
  double top_band = 0.25;          // in front of a wall has none there
  double max_seen_over = 0.5;      // share of its middle: a wall seen over along more (seen_over_share,
                                   // above its top band) is furniture under the ceiling; a wall is seen
                                   // through only at its doors, a chimney breast's front not at all
  double max_door_width = 1.0;     // m: a wall seen through a gap this narrow between two runs of one
                                   // nearer wall is outside (a single door; wider may be an L's arm)
  double min_hidden_wall = 0.1;    // m: parallel neighbours at least this far apart are joined by an
                                   // inferred wall (the shallowest chimney breasts and alcoves are 0.3 m)
};

// What the scanner can see above it: the ceiling (or the cloud's top) and its steepest upward
// ray. A surface at horizontal distance t shows up to min(top, t * tan_elevation).
struct ViewLimits {
  double top = 0;            // m above the scanner
  double tan_elevation = 1;  // of the steepest upward ray

  // The highest point seen on a surface at horizontal distance t, below a wall's top band:
  // where a wall has points and furniture in front of one has none.
  double top_at(double t) const { return std::min(top, t * tan_elevation); }
};

// An opening in a wall: returns seen beyond its line through a gap in it (a door, a window).
struct Opening {
  double start = 0, width = 0;  // m along the wall from its first corner
  double depth = 0;             // m: median distance past the wall's line of the returns seen through it
                                // at the wall's middle heights (0: none there, e.g. a window onto sky)
};

// A sector of the turn around the scanner where no wall is seen: from `first` to `last`, rad,
// counter-clockwise (first may be negative where it spans angle 0).
struct Sector {
  double first = 0, last = 0;
};

// The sectors wider than `min_width_deg` where no wall encloses the scanner (as room_polygon
// sees the walls): an open side, or a wall whose few returns (far, glass) made no plane of the
// whole cloud's size.
std::vector<Sector> open_sectors(const std::vector<WallLine>& walls, const ViewLimits& view,
                                 const PolygonSettings& settings, double min_width_deg);

// A gap in the turn from a wall into a recess behind it, or out again (an alcove's back and
// the wall either side of it, parallel), with the walls ordered as room_polygon orders them
// but keeping a wall seen through a door-wide gap: the recess's side faces the scanner there
// but, short and seen obliquely, made no plane of the whole cloud's size. `sector` is the gap
// widened by `margin_deg` either side, to hold the side's ends (a side seen edge on leaves a
// gap of a fraction of a degree, or none).
struct Step {
  Sector sector;
  size_t before = 0, after = 0;  // the parallel walls, indices into the walls
  double leave = 0, enter = 0;   // rad: the turn's last ray on `before` and first on `after`
};
std::vector<Step> step_gaps(const std::vector<WallLine>& walls, const ViewLimits& view, const PolygonSettings& settings,
                            double margin_deg);

// Whether `side` joins the step: it meets each of the step's walls within `reach` of one of its
// own ends and of where the turn leaves or meets that wall (the corners bound the gap). A
// wardrobe's face in a corner meets them elsewhere.
bool joins_step(const WallLine& side, const std::vector<WallLine>& walls, const Step& step, double reach);

// The room's walls in order: turning once around the scanner (the origin), the room's wall in
// each direction is the nearest wall the ray meets where the wall has points (the wall above a
// door counts: what is seen through the door is outside) and that reaches the top of what the
// scanner sees there (furniture in front of a wall does not); between parallel neighbours one
// behind the other a hidden wall is inferred (appended to `walls`, `inferred` set); then
// neighbours are intersected. Fails with a message when the walls do not close a room.
std::optional<Polygon> room_polygon(std::vector<WallLine>& walls, const ViewLimits& view,
                                    const PolygonSettings& settings, std::string& why);

// Openings along the wall from corner a to corner b: runs of at least `min_width` where more
// points lie beyond the wall's line (by `beyond`) than on it, with how deep what is seen
// through them lies.
std::vector<Opening> find_openings(const WallLine& wall, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                   const std::vector<Eigen::Vector3f>& points, double band, double beyond,
                                   double min_width);

double polygon_area(const std::vector<Eigen::Vector2d>& corners);
double signed_area(const std::vector<Eigen::Vector2d>& corners);   // positive counter-clockwise
double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b);  // z of the plane vectors' cross product

// How far past their corner, along `wall`, `neighbour` stands kNeighbourClearance off the wall's
// line: at a shallow corner the neighbour's points lie close to the wall's line well past the
// corner, and a wall running on past it is looked for only farther.
constexpr double kNeighbourClearance = 0.2;  // m: a wall's band (4 cm) and 3 sigmas of range noise at 4 m
double clear_of_neighbour(const WallLine& wall, const WallLine& neighbour);

// Where the lines na . p = oa and nb . p = ob meet (they must not be parallel).
Eigen::Vector2d intersect_lines(const Eigen::Vector2d& na, double oa, const Eigen::Vector2d& nb, double ob);

}  // namespace scanbus::room_measurement
