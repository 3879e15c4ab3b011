#include "scanbus/room_measurement/walls.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace scanbus::room_measurement {

Eigen::Vector3d WallLine::on_ray(const Eigen::Vector3d& point) const {
  return point * (offset / std::max(1e-9, normal.dot(point.head<2>())));
}

double WallLine::along_on_ray(const Eigen::Vector2d& point) const {
  return direction().dot(point * (offset / std::max(1e-9, normal.dot(point))));
}

namespace {

double percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0;
  const size_t index = std::min(values.size() - 1, static_cast<size_t>(fraction * (values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(index), values.end());
  return values[index];
}

// The sampling step among sorted positions: the median gap between distinct ones (revolutions
// sampling the same direction stack their returns within a centimetre), over at most
// `max_gaps` gaps counted back from `last`.
double sampling_step(const std::vector<double>& sorted, size_t last, size_t max_gaps) {
  constexpr double kDistinct = 0.01;  // m
  std::vector<double> gaps;
  for (size_t i = last; i > 0 && i < sorted.size() && gaps.size() < max_gaps; --i)
    if (sorted[i] - sorted[i - 1] > kDistinct) gaps.push_back(sorted[i] - sorted[i - 1]);
  if (gaps.empty()) return kDistinct;
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<long>(gaps.size() / 2), gaps.end());
  return gaps[gaps.size() / 2];
}

// Which `slot`-wide slots between low and high hold at least one value.
std::vector<bool> occupied_slots(const std::vector<double>& values, double low, double high, double slot) {
  const int slots = std::max(1, static_cast<int>(std::ceil((high - low) / slot)));
  std::vector<bool> occupied(static_cast<size_t>(slots), false);
  for (double v : values)
    if (v >= low && v <= high) occupied[std::min(slots - 1, static_cast<int>((v - low) / slot))] = true;
  return occupied;
}

// Share of those slots that hold a value.
double coverage(const std::vector<double>& values, double low, double high, double slot) {
  const std::vector<bool> occupied = occupied_slots(values, low, high, slot);
  return static_cast<double>(std::count(occupied.begin(), occupied.end(), true)) / static_cast<double>(occupied.size());
}

// The longest run of empty slots, in the values' unit.
double widest_gap(const std::vector<double>& values, double low, double high, double slot) {
  int widest = 0, run = 0;
  for (bool filled : occupied_slots(values, low, high, slot)) widest = std::max(widest, run = filled ? 0 : run + 1);
  return widest * slot;
}

// A wall where the turn around the scanner sees it: the angles of its first and last rays.
struct SeenWall {
  size_t wall;
  double first, last;  // rad, counter-clockwise; first may be negative where the run wraps
};

bool segments_cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& d) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a), d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}

// Whether a wall has points just below `top` within `reach` of an along-position (furniture
// has none) and is not seen over (furniture under the ceiling).
bool stands_to_top(const WallLine& wall, double along, double reach, double top, const PolygonSettings& settings) {
  return wall.seen_over <= settings.max_seen_over &&
         wall.profile.has_points(along, reach, top - settings.top_band, top);
}

// Whether it does so somewhere along it, with the view's top where each part of it lies (a
// wardrobe's face beside the scanner is seen to stop under it at its far end), and where:
// - Ceiling: at a part where the view reaches the ceiling (a wall);
// - ViewOnly: only at parts where the view ends below the ceiling (near the scanner): a wall
//   and furniture taller than the view there look alike;
// - Stops: nowhere (furniture).
// Not within support_reach of its ends, where a wall it meets in a corner stands on its line:
// a face shorter than twice that always Stops.
enum class TopSeen { Ceiling, ViewOnly, Stops };
TopSeen top_seen(const WallLine& wall, const ViewLimits& view, const PolygonSettings& settings) {
  const double step = wall.profile.slot;
  bool view_only = false;
  for (double along = wall.start + settings.support_reach; along <= wall.end - settings.support_reach; along += step) {
    const double t = std::hypot(wall.offset, along);
    if (!stands_to_top(wall, along, step / 2, view.top_at(t) - settings.top_margin, settings)) continue;
    if (view.top_at(t) >= view.top) return TopSeen::Ceiling;
    view_only = true;
  }
  return view_only ? TopSeen::ViewOnly : TopSeen::Stops;
}

bool reaches_top(const WallLine& wall, const ViewLimits& view, const PolygonSettings& settings) {
  return top_seen(wall, view, settings) != TopSeen::Stops;
}

// Whether the ray at `angle` meets `near`'s line before `far`'s.
bool in_front(const WallLine& near, const WallLine& far, double angle) {
  const Eigen::Vector2d ray(std::cos(angle), std::sin(angle));
  const double facing_far = far.normal.dot(ray), facing_near = near.normal.dot(ray);
  return facing_near > 0 && (facing_far <= 0 || near.offset / facing_near < far.offset / facing_far);
}

// Where the ray at `angle` meets a wall's line, as an along-position on it.
double along_at(const WallLine& wall, double angle) { return wall.along_on_ray({std::cos(angle), std::sin(angle)}); }

// Furniture in a corner (a wardrobe against wall A beside wall B) turns the outline from A to
// its side (parallel to B, nearer), its front (parallel to A, nearer) and B: a notch, with no
// two parallel neighbours. When neither face reaches the top of the view both are furniture,
// and A meets B behind them (Dropped). When neither is seen to reach the ceiling but one
// reaches the top of a view that ends below it, the notch may be either (Ambiguous, `why`).
enum class CornerFurniture { None, Dropped, Ambiguous };
CornerFurniture drop_corner_furniture(const std::vector<WallLine>& walls, const ViewLimits& view,
                                      const PolygonSettings& settings, double min_sine, std::vector<SeenWall>& order,
                                      std::string& why) {
  auto nearer_parallel = [&](const WallLine& near, const WallLine& far) {
    return std::abs(cross(near.normal, far.normal)) < min_sine && near.normal.dot(far.normal) > 0 &&
           near.offset < far.offset;
  };
  const size_t count = order.size();
  if (count < 5) return CornerFurniture::None;  // three walls stay
  for (size_t i = 0; i < count; ++i) {
    const size_t side = (i + 1) % count, front = (i + 2) % count;
    const WallLine& a = walls[order[i].wall];
    const WallLine& b = walls[order[(i + 3) % count].wall];
    if (std::abs(cross(a.normal, b.normal)) < min_sine || !nearer_parallel(walls[order[side].wall], b) ||
        !nearer_parallel(walls[order[front].wall], a))
      continue;
    const TopSeen side_top = top_seen(walls[order[side].wall], view, settings);
    const TopSeen front_top = top_seen(walls[order[front].wall], view, settings);
    if (side_top == TopSeen::Ceiling || front_top == TopSeen::Ceiling) continue;
    if (side_top == TopSeen::ViewOnly || front_top == TopSeen::ViewOnly) {
      why =
          "a corner is cut by two faces so near the scanner that the view ends below the ceiling over them: "
          "a wardrobe or the room's walls cannot be told apart";
      return CornerFurniture::Ambiguous;
    }
    order.erase(order.begin() + static_cast<long>(std::max(side, front)));
    order.erase(order.begin() + static_cast<long>(std::min(side, front)));
    return CornerFurniture::Dropped;
  }
  return CornerFurniture::None;
}

// Dropping a wall leaves the same wall on both sides of the gap: one run. The run over angle 0
// starts before it (`first` negative), as walls_around numbers it.
void merge_repeats(std::vector<SeenWall>& order) {
  for (size_t i = 0; i + 1 < order.size();) {
    if (order[i].wall == order[i + 1].wall) {
      order[i].last = order[i + 1].last;
      order.erase(order.begin() + static_cast<long>(i) + 1);
    } else {
      ++i;
    }
  }
  if (order.size() > 1 && order.front().wall == order.back().wall) {
    order.front().first = order.back().first - 2 * M_PI;
    order.pop_back();
  }
}

// The walls in the turn that are not the room's (occluders), dropped until none is left:
// - a wall across another, in front of it, between two runs of it;
// - of two parallel neighbours (they cannot meet in a corner): a farther one seen through a
//   door-wide gap in the nearer, or a nearer one that does not reach the top of the view,
//   furniture in front of the other (a wardrobe whose wall above the histogram filter
//   dropped), so the wall behind meets its true neighbours; a nearer one that reaches the top
//   is a wall, and the wall between them is missing (inferred later);
// - the two faces of furniture in a corner (drop_corner_furniture).
// False, with `why`, when a corner's faces cannot be told from walls.
bool drop_occluders(const std::vector<WallLine>& walls, const ViewLimits& view, const PolygonSettings& settings,
                    std::vector<SeenWall>& order, bool keep_through_gaps, std::string& why) {
  const double min_sine = std::sin(settings.min_wall_angle_deg * M_PI / 180);
  bool changed = true;
  while (changed && order.size() >= 3) {
    changed = false;
    for (size_t i = 0; i < order.size() && !changed; ++i) {
      const size_t next = (i + 1) % order.size();
      const WallLine& a = walls[order[i].wall];
      const WallLine& b = walls[order[next].wall];
      const size_t after = (i + 2) % order.size();
      // A wall across another, seen in front of it between two runs of it, is no side of the
      // room: the outline cannot leave a wall and come back onto it at one turn. It is the side
      // of furniture standing on that wall, seen edge-on where it meets the wall above it, or
      // the rays flickering between two walls at their corner. (Behind the wall's line it may be
      // an arm's side seen through the arm's opening.)
      if (order[i].wall == order[after].wall && std::abs(cross(a.normal, b.normal)) >= min_sine &&
          in_front(b, a, (order[next].first + order[next].last) / 2)) {
        order.erase(order.begin() + static_cast<long>(next));
        changed = true;
        continue;
      }
      if (std::abs(cross(a.normal, b.normal)) >= min_sine || a.normal.dot(b.normal) < 0) continue;
      // A wall seen between two runs of one nearer wall lies beyond a gap in it: outside, when
      // the gap is a door's (its lintel above the view, as from inside a closet). A wider gap
      // may be the room going on (an L's or T's arm whose sides are not seen): not decided here.
      // The runs end support_reach inside the gap's edges.
      const double gap =
          std::abs(along_at(a, order[after].first) - along_at(a, order[i].last)) + 2 * settings.support_reach;
      if (!keep_through_gaps && order.size() >= 4 && order[i].wall == order[after].wall && b.offset > a.offset &&
          gap <= settings.max_door_width) {
        order.erase(order.begin() + static_cast<long>(next));
        changed = true;
        continue;
      }
      const size_t nearer = a.offset < b.offset ? i : next;
      if (reaches_top(walls[order[nearer].wall], view, settings)) continue;  // a wall (an alcove's side is missing)
      order.erase(order.begin() + static_cast<long>(nearer));
      changed = true;
    }
    if (!changed) {
      const CornerFurniture corner = drop_corner_furniture(walls, view, settings, min_sine, order, why);
      if (corner == CornerFurniture::Ambiguous) return false;
      changed = corner == CornerFurniture::Dropped;
    }
    merge_repeats(order);
  }
  return true;
}

// Past its inliers' ends by more than this, points on a wall's line are not its own (a crossing
// wall's range noise far away, ground seen through a door) unless it is seen above furniture.
constexpr double kOwnStretch = 0.5;  // m

// Whether a seen wall has points at wall heights well past its corner with `neighbour`
// (`direction` +1: past its end side, -1: its start side), and is not seen through there: it
// goes on behind its neighbour, so the corner is not one (the neighbour's end stands in front of
// it, and a wall between them is hidden). Returns crossing its line there show a gap above what
// stands on it (a desk under a window, between two pillars): the wall's end is the corner. At a
// shallow corner it is looked at only past where the neighbour is clear of its line
// (clear_of_neighbour), at most kFarthest past the corner: under a 20-degree turn the
// neighbour's own points may then count, and the room is refused rather than closed.
bool runs_past(const WallLine& wall, const WallLine& neighbour, const Eigen::Vector2d& corner, int direction) {
  constexpr double kPast = 0.25, kFarthest = 0.6, kReach = 0.05, kLow = 0.3, kHigh = 1.5;  // m
  if (wall.inferred) return false;
  const double past = std::clamp(kReach + clear_of_neighbour(wall, neighbour), kPast, kFarthest);
  const double along = wall.direction().dot(corner) + direction * past, base = wall.profile.base;
  if (along < wall.start - kOwnStretch || along > wall.end + kOwnStretch) return false;
  return wall.profile.has_points(along, kReach, base + kLow, base + kHigh) &&
         !wall.profile.seen_through(along, kReach, base + kLow);
}

// A face standing out from the wall behind it by this or less may be tall furniture (wardrobes
// are 0.6 m deep, bookshelves less) or a chimney breast; an L's or a T's arm is deeper.
constexpr double kFurnitureDepth = 0.8;  // m

// Whether `back` is a recess's back beside `beyond`: parallel to it (within `angle`) and at
// least `min_step` behind it (a recess has a nearer wall either side of its back).
bool recess_beside(const WallLine& back, const WallLine& beyond, double angle, double min_step) {
  return hides_a_wall(back, beyond, angle, min_step) && beyond.offset < back.offset;
}

// Whether a recess's side was found where `hidden` would stand (step_sides: seen nearly edge
// on, over too short a turn to be a wall of the outline, its few grazing returns placing it
// centimetres off): the back is then seen past the side's foot, and the side is there.
bool side_found(const std::vector<WallLine>& walls, const WallLine& hidden) {
  constexpr double kReach = 0.1;  // m between the side's line and where the hidden wall would stand
  const double parallel = std::cos(10 * M_PI / 180);
  const Eigen::Vector2d middle = hidden.normal * hidden.offset + hidden.direction() * (hidden.start + hidden.end) / 2;
  return std::any_of(walls.begin(), walls.end(), [&](const WallLine& wall) {
    const double along = wall.direction().dot(middle);
    return wall.step_side && std::abs(wall.normal.dot(hidden.normal)) > parallel &&
           std::abs(wall.normal.dot(middle) - wall.offset) <= kReach && along >= wall.start - kReach &&
           along <= wall.end + kReach;
  });
}

// Between parallel neighbours one behind the other, the wall the scanner could not see:
// where the turn leaves the nearer wall (its end, a corner seen) the farther one is seen from
// the shadow's edge on, away from where the hidden wall meets it. Otherwise something else
// hides the gap, or the wall would have faced the scanner (a door's far side seen through the
// door): no wall is inferred (unless a recess's side was found there, seen edge on), and the
// outline will not close. Nor out of a face that a wardrobe could be (listed in `ambiguous`).
void insert_hidden_walls(std::vector<WallLine>& walls, const ViewLimits& view, const PolygonSettings& settings,
                         std::vector<SeenWall>& order, std::vector<size_t>& ambiguous) {
  constexpr double kShadowTolerance = 0.3;  // m along the farther wall between the shadow's edge and its first points
  constexpr double kEdge = 0.05;            // m: the shadow's edge, as the nearer wall's end is known
  constexpr double kParallel = 10 * M_PI / 180;  // closer to parallel than a corner could be, yet not one wall
  for (size_t i = 0; order.size() >= 2 && i < order.size(); ++i) {
    const size_t next = (i + 1) % order.size();
    const WallLine& before = walls[order[i].wall];  // these references used only before walls grows below
    const WallLine& after = walls[order[next].wall];
    if (before.inferred || after.inferred || !hides_a_wall(before, after, kParallel, settings.min_hidden_wall))
      continue;
    const bool before_nearer = before.offset < after.offset;
    const WallLine& nearer = before_nearer ? before : after;
    const WallLine& farther = before_nearer ? after : before;
    const double nearer_angle = before_nearer ? order[i].last : order[next].first;   // the turn's last ray on it
    const double farther_angle = before_nearer ? order[next].first : order[i].last;  // and first on the farther
    const double end = along_at(nearer, nearer_angle);
    const double shadow = along_at(farther, nearer_angle), first_seen = along_at(farther, farther_angle);
    if (std::abs(first_seen - shadow) > kShadowTolerance) continue;
    WallLine hidden = infer_hidden_wall(before, after, end);
    const double foot =
        farther.direction().dot(intersect_lines(farther.normal, farther.offset, hidden.normal, hidden.offset));
    // Into a recess (the farther wall's other neighbour nearer and parallel too) a side found
    // there stands in for the shadow: it is seen, edge on (not in front of furniture's face).
    // (Its neighbour among the seen walls: a side this loop inferred at its other end is skipped.)
    const size_t from = before_nearer ? next : i, count = order.size();
    size_t other = from;
    do other = before_nearer ? (other + 1) % count : (other + count - 1) % count;
    while (walls[order[other].wall].inferred && other != from);
    const WallLine& beyond = walls[order[other].wall];
    const bool recess =
        count >= 3 && &beyond != &nearer && recess_beside(farther, beyond, kParallel, settings.min_hidden_wall);
    if ((before_nearer ? foot > shadow + kEdge : foot < shadow - kEdge) && !(recess && side_found(walls, hidden)))
      continue;
    // Standing out from the wall behind by a wardrobe's depth or less, where the view ends below
    // the ceiling over it: a chimney breast, or tall furniture (its top above the view) taken for one.
    if (!recess && farther.offset - nearer.offset <= kFurnitureDepth &&
        top_seen(nearer, view, settings) == TopSeen::ViewOnly) {
      ambiguous.push_back(order[before_nearer ? i : next].wall);
      continue;
    }
    walls.push_back(std::move(hidden));
    order.insert(order.begin() + static_cast<long>(i) + 1, SeenWall{walls.size() - 1, nearer_angle, farther_angle});
    ++i;
  }
}

}  // namespace

bool hides_a_wall(const WallLine& before, const WallLine& after, double angle, double min_step) {
  return before.normal.dot(after.normal) > std::cos(angle) && std::abs(before.offset - after.offset) >= min_step;
}

WallLine infer_hidden_wall(const WallLine& before, const WallLine& after, double nearer_end) {
  const WallLine& nearer = before.offset < after.offset ? before : after;
  const WallLine& farther = before.offset < after.offset ? after : before;
  WallLine hidden;
  hidden.inferred = true;
  hidden.normal = nearer_end >= 0 ? nearer.direction() : Eigen::Vector2d(-nearer.direction());
  hidden.offset = std::abs(nearer_end);
  // Its extent: from the nearer wall's line to the farther one's, along its own direction.
  const Eigen::Vector2d seen = intersect_lines(nearer.normal, nearer.offset, hidden.normal, hidden.offset);
  const Eigen::Vector2d unseen = intersect_lines(farther.normal, farther.offset, hidden.normal, hidden.offset);
  hidden.start = std::min(hidden.direction().dot(seen), hidden.direction().dot(unseen));
  hidden.end = std::max(hidden.direction().dot(seen), hidden.direction().dot(unseen));
  hidden.z_low = std::min(nearer.z_low, farther.z_low);
  hidden.z_high = std::max(nearer.z_high, farther.z_high);
  return hidden;
}

WallEnd wall_end(const WallLine& wall, double near, bool at_end, const std::vector<Eigen::Vector3f>& points,
                 double band, double max_gap) {
  constexpr size_t kLast = 10;   // gaps whose median tells how finely the end is sampled
  constexpr double kBack = 0.3;  // m inside `near` the walk starts (not from the wall's middle: a
                                 // door on the way would stop it, and one line may hold two walls)
  const double sign = at_end ? 1 : -1;
  const double start = near - sign * kBack;
  // Where each point's ray meets the line, not the point: range noise moves a point along its
  // ray, and the most stretched of many would overshoot the end by a few centimetres.
  std::vector<double> along;  // from the start, towards the end
  for (const auto& p : points) {
    const Eigen::Vector2d xy = p.head<2>().cast<double>();
    const double facing = wall.normal.dot(xy);
    if (facing <= 1e-6 || std::abs(facing - wall.offset) > band) continue;
    const double s = sign * (wall.along_on_ray(xy) - start);
    if (s >= 0) along.push_back(s);
  }
  std::sort(along.begin(), along.end());
  size_t last = 0;
  while (last + 1 < along.size() && along[last + 1] - along[last] <= max_gap) ++last;
  WallEnd end;
  if (along.empty()) {
    end.along = near;
    end.spacing = max_gap;
    return end;
  }
  // The last sample falls short of the true end by up to a sampling step.
  end.spacing = sampling_step(along, last, kLast);
  end.along = start + sign * along[last];
  return end;
}

WallLine fit_wall(std::vector<Eigen::Vector3f> inliers) {
  WallLine wall;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : inliers) mean += p.head<2>().cast<double>();
  mean /= static_cast<double>(inliers.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : inliers) {
    const Eigen::Vector2d q = p.head<2>().cast<double>() - mean;
    scatter += q * q.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  wall.normal = solver.eigenvectors().col(0);  // smallest eigenvalue first
  wall.offset = wall.normal.dot(mean);
  if (wall.offset < 0) {  // face the scanner: the normal points from the origin to the wall
    wall.normal = -wall.normal;
    wall.offset = -wall.offset;
  }
  const auto n = static_cast<double>(inliers.size());
  wall.rms = std::sqrt(std::max(0.0, solver.eigenvalues()(0)) / n);
  wall.offset_sigma = wall.rms / std::sqrt(n);
  std::vector<double> along, heights;
  for (const auto& p : inliers) {
    along.push_back(wall.direction().dot(p.head<2>().cast<double>()));
    heights.push_back(p.z());
  }
  wall.start = percentile(along, 0.01);
  wall.end = percentile(along, 0.99);
  wall.z_low = percentile(heights, 0.02);
  wall.z_high = percentile(heights, 0.98);
  wall.z_coverage = coverage(heights, wall.z_low, wall.z_high, 0.1);
  wall.z_gap = widest_gap(heights, wall.z_low, wall.z_high, 0.1);
  wall.length_coverage = coverage(along, wall.start, wall.end, 0.1);
  wall.inliers = std::move(inliers);
  return wall;
}

std::vector<Eigen::Vector3f> long_runs(const WallLine& wall, double gap, double min_run) {
  std::vector<std::pair<double, size_t>> along;  // position along the line, inlier
  for (size_t i = 0; i < wall.inliers.size(); ++i)
    along.emplace_back(wall.direction().dot(wall.inliers[i].head<2>().cast<double>()), i);
  std::sort(along.begin(), along.end());
  std::vector<Eigen::Vector3f> kept;
  for (size_t first = 0, last = 0; first < along.size(); first = ++last) {
    while (last + 1 < along.size() && along[last + 1].first - along[last].first <= gap) ++last;
    if (along[last].first - along[first].first < min_run) continue;
    for (size_t k = first; k <= last; ++k) kept.push_back(wall.inliers[along[k].second]);
  }
  return kept;
}

namespace {

// Whether `small` is a sliver of `big`: RANSAC's plane through the noise on both sides of a far
// wall's band, turned a few degrees from it (more than merge_collinear's angle), its points
// within `tail` of the wall's line and within its length.
bool sliver_of(const WallLine& small, const WallLine& big, double tail) {
  constexpr double kMaxTurn = 10 * M_PI / 180;
  constexpr double kShare = 0.9;  // of the sliver's points
  if (small.normal.dot(big.normal) < std::cos(kMaxTurn)) return false;
  size_t near = 0;
  for (const auto& p : small.inliers) {
    const Eigen::Vector2d xy = p.head<2>().cast<double>();
    const double along = big.direction().dot(xy);
    near += std::abs(big.normal.dot(xy) - big.offset) < tail && along > big.start - tail && along < big.end + tail;
  }
  return near >= kShare * static_cast<double>(small.inliers.size());
}

}  // namespace

std::vector<WallLine> merge_collinear(std::vector<WallLine> walls, double angle, double same, double tail) {
  std::sort(walls.begin(), walls.end(),
            [](const auto& a, const auto& b) { return a.inliers.size() > b.inliers.size(); });
  for (size_t i = 0; i < walls.size(); ++i) {
    for (size_t j = i + 1; j < walls.size();) {
      const double gap = std::abs(walls[i].offset - walls[j].offset);
      const bool parallel = walls[i].normal.dot(walls[j].normal) > std::cos(angle);
      if (parallel && gap < same) {
        auto points = walls[i].inliers;
        points.insert(points.end(), walls[j].inliers.begin(), walls[j].inliers.end());
        walls[i] = fit_wall(std::move(points));
        walls.erase(walls.begin() + static_cast<long>(j));
        j = i + 1;
      } else if ((parallel && gap < tail) || sliver_of(walls[j], walls[i], tail)) {
        walls.erase(walls.begin() + static_cast<long>(j));
      } else {
        ++j;
      }
    }
  }
  return walls;
}

namespace {

// Whether any slot within `reach` of an along-position has a bit set between z_low and z_high.
bool any_in(const WallProfile& profile, const std::vector<uint64_t>& grid, double along, double reach, double z_low,
            double z_high) {
  uint64_t wanted = ~0ULL;  // the height cells between z_low and z_high
  if (z_low > -1e8) {
    // Only cells wholly above z_low: a cell reaching below it may hold just points under it.
    const long low = std::clamp(static_cast<long>(std::ceil((z_low - profile.base) / profile.cell)), 0L, 64L);
    const long high = std::clamp(static_cast<long>(std::floor((z_high - profile.base) / profile.cell)), -1L, 63L);
    if (high < low) return false;
    wanted = (high - low == 63 ? ~0ULL : ((1ULL << (high - low + 1)) - 1)) << low;
  }
  const long first = std::max(0L, static_cast<long>(std::floor((along - reach - profile.origin) / profile.slot)));
  const long last = std::min(static_cast<long>(grid.size()) - 1,
                             static_cast<long>(std::floor((along + reach - profile.origin) / profile.slot)));
  for (long i = first; i <= last; ++i)
    if (grid[static_cast<size_t>(i)] & wanted) return true;
  return false;
}

}  // namespace

bool WallProfile::has_points(double along, double reach, double z_low, double z_high) const {
  return any_in(*this, cells, along, reach, z_low, z_high);
}

bool WallProfile::seen_through(double along, double reach, double z_low, double z_high) const {
  return any_in(*this, through, along, reach, z_low, z_high);
}

WallProfile wall_profile(const WallLine& wall, const std::vector<Eigen::Vector3f>& points, double band, double beyond,
                         double margin) {
  WallProfile profile;
  profile.origin = wall.start - margin;
  const auto slots = static_cast<size_t>(std::ceil((wall.end - wall.start + 2 * margin) / profile.slot)) + 1;
  profile.cells.assign(slots, 0);
  profile.through.assign(slots, 0);
  const Eigen::Vector2f normal = wall.normal.cast<float>(), direction = wall.direction().cast<float>();
  auto slot_of = [&](double along) { return std::floor((along - profile.origin) / profile.slot); };
  std::vector<std::pair<size_t, float>> near, crossing;  // slot, height
  float low = std::numeric_limits<float>::max(), high = std::numeric_limits<float>::lowest();
  for (const auto& p : points) {
    const double distance = normal.dot(p.head<2>()) - static_cast<float>(wall.offset);
    if (distance > beyond) {  // where its ray crosses the line
      const Eigen::Vector3d at = wall.on_ray(p.cast<double>());
      const double slot = slot_of(wall.direction().dot(at.head<2>()));
      if (slot >= 0 && slot < static_cast<double>(slots)) crossing.emplace_back(static_cast<size_t>(slot), at.z());
      continue;
    }
    if (std::abs(distance) > band) continue;
    const double along = direction.dot(p.head<2>());
    const double slot = slot_of(along);
    if (slot < 0 || slot >= static_cast<double>(slots)) continue;
    near.emplace_back(static_cast<size_t>(slot), p.z());
    if (along < wall.start - kOwnStretch || along > wall.end + kOwnStretch) continue;  // heights of its own
    low = std::min(low, p.z());
    high = std::max(high, p.z());
  }
  if (near.empty() || low > high) return profile;
  profile.base = low;
  profile.cell = std::max(0.05, (high - low) / 63.9);
  auto cell_of = [&](float z) { return std::clamp(static_cast<int>(std::floor((z - low) / profile.cell)), 0, 63); };
  for (const auto& [slot, z] : near) profile.cells[slot] |= 1ULL << cell_of(z);
  for (const auto& [slot, z] : crossing) profile.through[slot] |= 1ULL << cell_of(z);
  return profile;
}

double seen_over_share(const WallLine& wall, const std::vector<Eigen::Vector3f>& points, double beyond, double margin,
                       double z_from) {
  constexpr double kSlot = 0.1;  // m
  const double first = wall.start + margin, length = wall.end - margin - first;
  if (!(length >= kSlot)) return 0;
  std::vector<bool> over(static_cast<size_t>(std::ceil(length / kSlot)), false);
  for (const auto& p : points) {
    const Eigen::Vector2d xy = p.head<2>().cast<double>();
    if (wall.normal.dot(xy) - wall.offset <= beyond) continue;
    const Eigen::Vector3d crossing = wall.on_ray(p.cast<double>());
    const double s = wall.direction().dot(crossing.head<2>()) - first;
    if (crossing.z() > z_from && s >= 0 && s < length) over[static_cast<size_t>(s / kSlot)] = true;
  }
  // Only where the wall stands below (a gap in its line, an L's or T's arm, is no furniture).
  constexpr double kAboveFloor = 0.3;  // m: floor points lie on every line
  size_t seen = 0;
  for (size_t i = 0; i < over.size(); ++i)
    seen += over[i] &&
            wall.profile.has_points(first + (i + 0.5) * kSlot, kSlot / 2, wall.profile.base + kAboveFloor, z_from);
  return static_cast<double>(seen) / static_cast<double>(over.size());
}

namespace {

constexpr int kSteps = 1440;  // rays around the scanner: a quarter of a degree each

// Runs of one wall (or none, -1) around the turn; the run over angle 0 is one run.
struct Run {
  int wall, first, length;  // steps
};

// The nearest enclosing wall in each direction, a quarter of a degree at a time, in runs. A
// wall that does not reach the top of the view is furniture when a wall stands behind it. Behind
// furniture a wall counts past its inliers' ends as far as its profile shows it: the wall above
// a wardrobe in a corner is no inlier (the histogram filter drops its short columns), and without
// it the wardrobe's faces close the room. Elsewhere the points past its ends are a crossing
// neighbour's, or a wall in line with it in the next room seen through a door. How far past its
// ends it may count is how far its profile reaches (describe_walls' margin).
std::vector<Run> enclosing_runs(const std::vector<WallLine>& walls, const ViewLimits& view,
                                const PolygonSettings& settings) {
  constexpr double kFloorBand = 0.15;  // m over the lowest point near a wall's line
  std::vector<int> seen(kSteps, -1);
  struct Hit {
    double t;
    int wall;
    bool past_ends;
  };
  std::vector<Hit> hits;
  for (int step = 0; step < kSteps; ++step) {
    const double angle = 2 * M_PI * step / kSteps;
    const Eigen::Vector2d ray(std::cos(angle), std::sin(angle));
    hits.clear();
    for (size_t w = 0; w < walls.size(); ++w) {
      const double facing = walls[w].normal.dot(ray);
      if (facing < 1e-6) continue;
      const double t = walls[w].offset / facing;
      const double along = walls[w].direction().dot(t * ray);
      const bool past_ends =
          along < walls[w].start - settings.extent_tolerance || along > walls[w].end + settings.extent_tolerance;
      // Points at a wall's own heights: the floor and ceiling run on under an alcove or a
      // chimney breast's side, where no wall stands on the line.
      const double top = view.top_at(t) - settings.top_margin;
      if (walls[w].profile.has_points(along, settings.support_reach, walls[w].profile.base + kFloorBand, top))
        hits.push_back({t, static_cast<int>(w), past_ends});
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t < b.t; });
    // Past its ends only behind furniture: behind a nearer wall within its ends.
    hits.erase(hits.begin(), std::find_if(hits.begin(), hits.end(), [](const Hit& hit) { return !hit.past_ends; }));
    if (hits.empty()) continue;
    // Nothing reaches the top: the farthest within its ends, as furniture stands in front.
    seen[step] = std::find_if(hits.rbegin(), hits.rend(), [](const Hit& hit) { return !hit.past_ends; })->wall;
    for (const Hit& hit : hits) {
      const double top = view.top_at(hit.t) - settings.top_margin;
      const double along = walls[hit.wall].direction().dot(hit.t * ray);
      if (stands_to_top(walls[hit.wall], along, settings.support_reach, top, settings)) {
        seen[step] = hit.wall;
        break;
      }
    }
  }
  std::vector<Run> runs;
  for (int step = 0; step < kSteps; ++step) {
    if (!runs.empty() && runs.back().wall == seen[step]) {
      ++runs.back().length;
    } else {
      runs.push_back({seen[step], step, 1});
    }
  }
  if (runs.size() > 1 && runs.front().wall == runs.back().wall) {
    runs.front().first = runs.back().first - kSteps;
    runs.front().length += runs.back().length;
    runs.pop_back();
  }
  return runs;
}

}  // namespace

std::vector<Sector> open_sectors(const std::vector<WallLine>& walls, const ViewLimits& view,
                                 const PolygonSettings& settings, double min_width_deg) {
  const int min_steps = static_cast<int>(min_width_deg / 360.0 * kSteps);
  std::vector<Sector> sectors;
  for (const Run& run : enclosing_runs(walls, view, settings))
    if (run.wall < 0 && run.length > min_steps)
      sectors.push_back({2 * M_PI * run.first / kSteps, 2 * M_PI * (run.first + run.length) / kSteps});
  return sectors;
}

namespace {

// The walls around the scanner in the order the turn meets them (enclosing_runs), occluders dropped.
std::optional<std::vector<SeenWall>> walls_around(const std::vector<WallLine>& walls, const ViewLimits& view,
                                                  const PolygonSettings& settings, std::string& why,
                                                  bool keep_through_gaps = false) {
  // Short runs are clutter.
  const std::vector<Run> runs = enclosing_runs(walls, view, settings);
  const int min_steps = static_cast<int>(settings.min_run_deg / 360.0 * kSteps);
  const int max_gap_steps = static_cast<int>(settings.max_gap_deg / 360.0 * kSteps);
  const double step_angle = 2 * M_PI / kSteps;
  std::vector<SeenWall> order;
  for (const Run& run : runs) {
    if (run.wall < 0) {  // corners and occlusions leave short gaps; corners come from intersections
      if (run.length > max_gap_steps) {
        why = "no wall seen over " + std::to_string(run.length / 4) + " degrees: the walls do not close a room";
        return std::nullopt;
      }
      continue;
    }
    if (run.length < min_steps) continue;
    const double first = run.first * step_angle, last = (run.first + run.length - 1) * step_angle;
    if (!order.empty() && order.back().wall == static_cast<size_t>(run.wall)) {
      order.back().last = last;
      continue;
    }
    order.push_back({static_cast<size_t>(run.wall), first, last});
  }
  merge_repeats(order);  // the run over angle 0
  if (!drop_occluders(walls, view, settings, order, keep_through_gaps, why)) return std::nullopt;
  return order;
}

}  // namespace

std::optional<Polygon> room_polygon(std::vector<WallLine>& walls, const ViewLimits& view,
                                    const PolygonSettings& settings, std::string& why) {
  std::optional<std::vector<SeenWall>> order = walls_around(walls, view, settings, why);
  if (!order) return std::nullopt;
  std::vector<size_t> ambiguous;  // faces left without hidden sides: furniture or a chimney breast
  insert_hidden_walls(walls, view, settings, *order, ambiguous);
  Polygon polygon;
  for (const auto& seen_wall : *order) polygon.walls.push_back(seen_wall.wall);
  if (polygon.walls.size() < 3) {
    why = "only " + std::to_string(polygon.walls.size()) + " walls around the scanner: not a room";
    return std::nullopt;
  }

  // Corners: each wall meets the next; neighbours must not be (nearly) parallel.
  Eigen::Vector2d low(1e9, 1e9), high(-1e9, -1e9);
  for (size_t w : polygon.walls)
    for (const auto& p : walls[w].inliers) {
      low = low.cwiseMin(p.head<2>().cast<double>());
      high = high.cwiseMax(p.head<2>().cast<double>());
    }
  const size_t count = polygon.walls.size();
  for (size_t i = 0; i < count; ++i) {
    const WallLine& a = walls[polygon.walls[(i + count - 1) % count]];
    const WallLine& b = walls[polygon.walls[i]];
    const double sine = std::abs(cross(a.normal, b.normal));
    if (sine < std::sin(settings.min_wall_angle_deg * M_PI / 180)) {
      const size_t number_a = i == 0 ? count : i, number_b = i + 1;
      const bool a_ambiguous = std::count(ambiguous.begin(), ambiguous.end(), polygon.walls[number_a - 1]) > 0;
      if (a_ambiguous || std::count(ambiguous.begin(), ambiguous.end(), polygon.walls[i]) > 0)
        why = "wall " + std::to_string(a_ambiguous ? number_a : number_b) + " stands out from wall " +
              std::to_string(a_ambiguous ? number_b : number_a) +
              " where the view ends below the ceiling: a chimney breast and tall furniture cannot be told apart, the "
              "walls do not close a room";
      else
        why = "neighbouring walls " + std::to_string(number_a) + " and " + std::to_string(number_b) +
              " are parallel: a wall between them is missing, the walls do not close a room";
      return std::nullopt;
    }
    const Eigen::Vector2d corner = intersect_lines(a.normal, a.offset, b.normal, b.offset);
    if ((corner.array() < low.array() - settings.corner_margin).any() ||
        (corner.array() > high.array() + settings.corner_margin).any()) {
      why = "walls " + std::to_string(i == 0 ? count : i) + " and " + std::to_string(i + 1) +
            " meet outside the scanned area: the walls do not close a room";
      return std::nullopt;
    }
    const bool a_runs_past = runs_past(a, b, corner, +1);
    if (a_runs_past || runs_past(b, a, corner, -1)) {
      const size_t number_a = i == 0 ? count : i, number_b = i + 1;
      why = "wall " + std::to_string(a_runs_past ? number_a : number_b) + " runs on past its corner with wall " +
            std::to_string(a_runs_past ? number_b : number_a) +
            ": a wall between them is not seen, the walls do not close a room";
      return std::nullopt;
    }
    polygon.corners.push_back(corner);
  }
  for (size_t i = 0; i < count; ++i)
    for (size_t j = i + 2; j < count; ++j) {
      if (i == 0 && j == count - 1) continue;  // neighbours share a corner
      if (segments_cross(polygon.corners[i], polygon.corners[(i + 1) % count], polygon.corners[j],
                         polygon.corners[(j + 1) % count])) {
        why = "the walls cross each other: not a simple room outline";
        return std::nullopt;
      }
    }
  return polygon;
}

std::vector<Step> step_gaps(const std::vector<WallLine>& walls, const ViewLimits& view, const PolygonSettings& settings,
                            double margin_deg) {
  std::string why;
  // A wall seen through a gap as narrow as a door stays: it may be an alcove's back.
  const std::optional<std::vector<SeenWall>> order = walls_around(walls, view, settings, why, true);
  if (!order || order->size() < 3) return {};                        // a recess has a wall either side
  const double parallel = settings.min_wall_angle_deg * M_PI / 180;  // closer, no corner joins them
  const double margin = margin_deg * M_PI / 180;
  std::vector<Step> steps;
  for (size_t i = 0; i < order->size(); ++i) {
    const SeenWall& before = (*order)[i];
    const SeenWall& after = (*order)[(i + 1) % order->size()];
    const double enter = after.first < before.last ? after.first + 2 * M_PI : after.first;
    const WallLine& a = walls[before.wall];
    const WallLine& b = walls[after.wall];
    if (!hides_a_wall(a, b, parallel, settings.min_hidden_wall)) continue;
    // Only into a recess (the farther wall's other neighbour nearer and parallel too): a
    // protrusion's found side would let its front meet the next wall where a hidden side and a
    // stretch of wall behind it may lie (measure_room cannot always tell; chimney breasts keep
    // to the hidden-wall inference; out of faces 0.9-1.4 m deep, searched too, two more of 60
    // such rooms were closed with wrong walls).
    const bool into = a.offset < b.offset;
    const WallLine& back = into ? b : a;
    const size_t other = into ? (i + 2) % order->size() : (i + order->size() - 1) % order->size();
    const WallLine& beyond = walls[(*order)[other].wall];
    if (!recess_beside(back, beyond, parallel, settings.min_hidden_wall)) continue;
    steps.push_back({{before.last - margin, enter + margin}, before.wall, after.wall, before.last, enter});
  }
  return steps;
}

bool joins_step(const WallLine& side, const std::vector<WallLine>& walls, const Step& step, double reach) {
  const auto meets_at_edge = [&](const WallLine& wall, double edge) {
    if (std::abs(cross(side.normal, wall.normal)) < 1e-3) return false;
    const Eigen::Vector2d corner = intersect_lines(side.normal, side.offset, wall.normal, wall.offset);
    const double on_side = side.direction().dot(corner);
    return std::min(std::abs(on_side - side.start), std::abs(on_side - side.end)) <= reach &&
           std::abs(wall.direction().dot(corner) - along_at(wall, edge)) <= reach;
  };
  return meets_at_edge(walls[step.before], step.leave) && meets_at_edge(walls[step.after], step.enter);
}

std::vector<Opening> find_openings(const WallLine& wall, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                   const std::vector<Eigen::Vector3f>& points, double band, double beyond,
                                   double min_width) {
  constexpr double kSlot = 0.05;  // m
  constexpr double kCell = 0.1;   // m of height: a door's header and a window's sill hold points on
  constexpr int kCells = 64;      // the line at other heights than what is seen through the gap
  const double length = (b - a).norm();
  if (!(length >= kSlot)) return {};
  const Eigen::Vector2d along = (b - a) / length;
  const auto slots = static_cast<size_t>(std::ceil(length / kSlot));
  const double base = wall.z_low - 0.5;
  std::vector<int> on(slots * kCells, 0), past(slots * kCells, 0);  // per slot and height cell
  std::vector<std::vector<double>> depths(slots);                   // past the line, at the wall's middle heights
  std::vector<std::vector<double>> passing(slots);                  // where returns pass the line
  const double middle_low = wall.z_low + 0.3, middle_high = wall.z_high - 0.3;
  for (const auto& p : points) {
    const Eigen::Vector2d xy = p.head<2>().cast<double>();
    const double distance = wall.normal.dot(xy) - wall.offset;  // > 0 beyond the wall
    if (distance < -band || wall.normal.dot(xy) < 1e-6) continue;
    const Eigen::Vector3d crossing = wall.on_ray(p.cast<double>());
    const double s = along.dot(crossing.head<2>() - a);
    if (!(s >= 0 && s < length)) continue;
    const auto slot = std::min(slots - 1, static_cast<size_t>(s / kSlot));
    const size_t cell =
        slot * kCells + static_cast<size_t>(std::clamp((crossing.z() - base) / kCell, 0.0, kCells - 1.0));
    if (distance <= band) ++on[cell];
    if (distance <= beyond) continue;
    ++past[cell];
    passing[slot].push_back(s);
    if (crossing.z() > middle_low && crossing.z() < middle_high) depths[slot].push_back(distance);
  }
  // A slot is open where more returns pass the line than stop on it at the heights they pass.
  std::vector<bool> open(slots, false);
  for (size_t slot = 0; slot < slots; ++slot) {
    int passing = 0, stopping = 0;
    for (size_t cell = slot * kCells; cell < (slot + 1) * kCells; ++cell)
      if (past[cell] > 0) {
        passing += past[cell];
        stopping += on[cell];
      }
    open[slot] = passing > stopping;
  }
  std::vector<Opening> openings;
  for (size_t i = 0; i < slots;) {
    if (!open[i]) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j < slots && open[j]) ++j;
    // Its ends where the outermost returns pass, in the open slots or the closed ones beside them
    // (a jamb falls anywhere in a slot), moved out by half the sampling step: the outermost
    // return falls short of the jamb by up to a step.
    std::vector<double> through;
    for (size_t k = i > 0 ? i - 1 : i; k <= std::min(j, slots - 1); ++k)
      through.insert(through.end(), passing[k].begin(), passing[k].end());
    std::sort(through.begin(), through.end());
    const double half_step = sampling_step(through, through.size() - 1, through.size()) / 2;
    const double start = std::max(0.0, through.front() - half_step);
    const double end = std::min(length, through.back() + half_step);
    if (end - start >= min_width) {
      std::vector<double> seen;
      for (size_t k = i; k < j; ++k) seen.insert(seen.end(), depths[k].begin(), depths[k].end());
      openings.push_back({start, end - start, percentile(std::move(seen), 0.5)});
    }
    i = j;
  }
  return openings;
}

double clear_of_neighbour(const WallLine& wall, const WallLine& neighbour) {
  // Normals point away from the scanner: past a turn of more than 90 degrees (a negative dot) the
  // neighbour runs back from the corner, clear of the wall's line at once.
  const double sine = std::abs(cross(wall.normal, neighbour.normal));
  return kNeighbourClearance * std::max(0.0, wall.normal.dot(neighbour.normal)) / std::max(sine, 1e-6);
}

Eigen::Vector2d intersect_lines(const Eigen::Vector2d& na, double oa, const Eigen::Vector2d& nb, double ob) {
  Eigen::Matrix2d lines;
  lines << na.transpose(), nb.transpose();
  return lines.inverse() * Eigen::Vector2d(oa, ob);
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double signed_area(const std::vector<Eigen::Vector2d>& corners) {
  double twice = 0;  // shoelace
  for (size_t i = 0; i < corners.size(); ++i) twice += cross(corners[i], corners[(i + 1) % corners.size()]);
  return twice / 2;
}

double polygon_area(const std::vector<Eigen::Vector2d>& corners) { return std::abs(signed_area(corners)); }

}  // namespace scanbus::room_measurement
