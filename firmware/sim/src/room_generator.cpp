#include "scanbus/sim/room_generator.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "scanbus/units.hpp"

namespace scanbus::sim {

namespace {

class Draw {
 public:
  explicit Draw(unsigned seed) : random(seed) {}
  double uniform(double low, double high) { return std::uniform_real_distribution<double>(low, high)(random); }
  bool chance(double p) { return uniform(0, 1) < p; }
  int integer(int low, int high) { return std::uniform_int_distribution<int>(low, high)(random); }
  std::mt19937 random;
};

bool inside(const std::vector<Eigen::Vector2d>& corners, const Eigen::Vector2d& p) {
  bool in = false;  // even-odd rule
  for (size_t i = 0, j = corners.size() - 1; i < corners.size(); j = i++) {
    const Eigen::Vector2d &a = corners[i], &b = corners[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

double distance_to_walls(const std::vector<Eigen::Vector2d>& corners, const Eigen::Vector2d& p) {
  double best = 1e9;
  for (size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector2d a = corners[i], edge = corners[(i + 1) % corners.size()] - a;
    const double s = std::clamp((p - a).dot(edge) / edge.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (p - (a + s * edge)).norm());
  }
  return best;
}

double distance_to_box(const Box& box, const Eigen::Vector2d& p) {
  const Eigen::Vector2d outside = (box.min.head<2>() - p).cwiseMax(p - box.max.head<2>()).cwiseMax(0.0);
  return outside.norm();
}

// A room that leaves no spot for the scanner's tripod (furniture, or walls too close): drawn again.
struct NoScannerSpot : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A spot for the scanner inside the room, clear of walls and furniture by the margins.
void place_scanner(RoomModel& room, Draw& draw, double wall_margin, double box_margin = 0.3) {
  Eigen::Vector2d low = room.corners.front(), high = low;
  for (const auto& c : room.corners) low = low.cwiseMin(c), high = high.cwiseMax(c);
  for (int attempt = 0; attempt < 10000; ++attempt) {
    const Eigen::Vector2d p(draw.uniform(low.x(), high.x()), draw.uniform(low.y(), high.y()));
    if (!inside(room.corners, p) || distance_to_walls(room.corners, p) < wall_margin) continue;
    if (std::any_of(room.boxes.begin(), room.boxes.end(),
                    [&](const Box& b) { return distance_to_box(b, p) < box_margin; }))
      continue;
    room.scanner = Eigen::Vector3d(p.x(), p.y(), draw.uniform(0.9, 1.5));
    return;
  }
  throw NoScannerSpot("no spot for the scanner clear of walls and furniture");
}

// Low furniture (beds, sofas, tables) standing free or against a wall of a w x d rectangle.
void add_low_furniture(RoomModel& room, Draw& draw, double w, double d, int count) {
  for (int i = 0; i < count; ++i) {
    const double sx = draw.uniform(0.5, std::min(2.0, w / 2)), sy = draw.uniform(0.4, std::min(1.6, d / 2));
    const double x = draw.uniform(0.05, w - sx - 0.05), y = draw.uniform(0.05, d - sy - 0.05);
    room.boxes.push_back({Eigen::Vector3d(x, y, 0), Eigen::Vector3d(x + sx, y + sy, draw.uniform(0.4, 0.9))});
  }
}

RoomModel rectangle(Draw& draw, double w, double d) {
  RoomModel room;
  room.corners = {{0, 0}, {w, 0}, {w, d}, {0, d}};
  room.ceiling = draw.uniform(2.3, 3.0);
  room.heading = draw.uniform(-M_PI, M_PI);
  return room;
}

// An opening on a wall of the polygon, `width` wide, kept 0.15 m from the wall's corners.
bool add_opening(RoomModel& room, Draw& draw, size_t wall, double width, double bottom, double top) {
  const double length = room.wall_lengths()[wall];
  if (length < width + 0.3) return false;
  const double from = draw.uniform(0.15, length - width - 0.15);
  for (const auto& o : room.openings)
    if (o.wall == wall && from < o.to + 0.2 && from + width > o.from - 0.2) return false;
  room.openings.push_back({wall, from, from + width, bottom, top});
  return true;
}

// A wall `behind` m outside the opening, parallel to its wall, running `reach` m either side.
void add_wall_behind(RoomModel& room, const Opening& opening, double behind, double reach) {
  const Eigen::Vector2d a = room.corners[opening.wall], b = room.corners[(opening.wall + 1) % room.corners.size()];
  const Eigen::Vector2d along = (b - a).normalized(),
                        out(along.y(), -along.x());  // counter-clockwise: outside is right
  const Eigen::Vector2d mid = a + along * (opening.from + opening.to) / 2 + out * behind;
  room.outside_walls.push_back({mid - along * reach, mid + along * reach});
}

void add_doors(RoomModel& room, Draw& draw, int count) {
  for (int i = 0, tries = 0; i < count && tries < 50; ++tries) {
    const size_t wall = static_cast<size_t>(draw.integer(0, static_cast<int>(room.corners.size()) - 1));
    if (!add_opening(room, draw, wall, draw.uniform(0.75, 0.95), 0, draw.uniform(1.95, 2.1))) continue;
    if (draw.chance(0.8)) add_wall_behind(room, room.openings.back(), draw.uniform(1.0, 3.0), draw.uniform(1.5, 4.0));
    ++i;
  }
}

void add_windows(RoomModel& room, Draw& draw, int count) {
  for (int i = 0, tries = 0; i < count && tries < 50; ++tries) {
    const size_t wall = static_cast<size_t>(draw.integer(0, static_cast<int>(room.corners.size()) - 1));
    const double top = std::min(room.ceiling - 0.15, draw.uniform(1.9, 2.3));
    if (!add_opening(room, draw, wall, draw.uniform(0.8, 1.8), draw.uniform(0.7, 1.0), top)) continue;
    if (draw.chance(0.5)) add_wall_behind(room, room.openings.back(), draw.uniform(6.0, 15.0), 10.0);
    ++i;
  }
}

// A recess (depth > 0) or protrusion (depth < 0) in the rectangle's bottom wall, `corner_gap`
// from one of its corners if given, anywhere along it if not.
RoomModel notched_rectangle(Draw& draw, double w, double d, double width, double depth,
                            std::optional<double> corner_gap = std::nullopt) {
  RoomModel room = rectangle(draw, w, d);
  const double a = !corner_gap        ? draw.uniform(0.3, w - width - 0.3)
                   : draw.chance(0.5) ? *corner_gap
                                      : w - width - *corner_gap;
  room.corners = {{0, 0}, {a, 0}, {a, -depth}, {a + width, -depth}, {a + width, 0}, {w, 0}, {w, d}, {0, d}};
  return room;
}

// A wardrobe or shelf against wall `side` (0 bottom, 1 right, 2 top, 3 left) of a w x d rectangle.
void add_tall_furniture(RoomModel& room, Draw& draw, double w, double d, int side, double depth, double height,
                        bool in_corner) {
  const double length = side % 2 == 0 ? w : d;
  const double width = draw.uniform(0.8, std::min(2.0, length * 0.45));
  const double start = in_corner ? 0.02 : draw.uniform(0.3, length - width - 0.3);
  Eigen::Vector3d min, max;
  switch (side) {
    case 0:
      min = {start, 0.02, 0}, max = {start + width, 0.02 + depth, height};
      break;
    case 1:
      min = {w - 0.02 - depth, start, 0}, max = {w - 0.02, start + width, height};
      break;
    case 2:
      min = {w - start - width, d - 0.02 - depth, 0}, max = {w - start, d - 0.02, height};
      break;
    default:
      min = {0.02, d - start - width, 0}, max = {0.02 + depth, d - start, height};
      break;
  }
  room.boxes.push_back({min, max});
}

RoomModel make_room(RoomCategory category, Draw& draw) {
  const double w = draw.uniform(3.0, 7.0), d = draw.uniform(2.6, 5.5);
  RoomModel room;
  switch (category) {
    case RoomCategory::Box:
      room = rectangle(draw, w, d);
      add_low_furniture(room, draw, w, d, draw.integer(0, 3));
      place_scanner(room, draw, 0.9);
      break;
    case RoomCategory::Doors:
      room = rectangle(draw, w, d);
      add_doors(room, draw, draw.integer(1, 2));
      add_low_furniture(room, draw, w, d, draw.integer(0, 2));
      place_scanner(room, draw, 0.9);
      break;
    case RoomCategory::Windows:
      room = rectangle(draw, w, d);
      add_windows(room, draw, draw.integer(1, 2));
      add_low_furniture(room, draw, w, d, draw.integer(0, 2));
      place_scanner(room, draw, 0.9);
      break;
    case RoomCategory::Alcove:
      room = notched_rectangle(draw, w, d, draw.uniform(0.8, 1.5), draw.uniform(0.3, 0.8));
      place_scanner(room, draw, 0.9);
      break;
    case RoomCategory::ChimneyBreast:
      room = notched_rectangle(draw, w, d, draw.uniform(1.0, 1.6), -draw.uniform(0.3, 0.6));
      place_scanner(room, draw, 0.9);
      break;
    case RoomCategory::LShape: {
      room = rectangle(draw, w, d);
      const double w2 = draw.uniform(0.4, 0.7) * w, d1 = draw.uniform(0.4, 0.7) * d;
      room.corners = {{0, 0}, {w, 0}, {w, d1}, {w2, d1}, {w2, d}, {0, d}};
      place_scanner(room, draw, 0.7);
      break;
    }
    case RoomCategory::TShape: {
      room = rectangle(draw, w, d);
      const double d1 = draw.uniform(0.45, 0.65) * d, stem = draw.uniform(0.35, 0.6) * w;
      const double c = draw.uniform(0.15, 0.85 - stem / w) * w;
      room.corners = {{0, 0}, {w, 0}, {w, d1}, {c + stem, d1}, {c + stem, d}, {c, d}, {c, d1}, {0, d1}};
      place_scanner(room, draw, 0.7);
      break;
    }
    case RoomCategory::Angled: {
      room = rectangle(draw, w, d);
      if (draw.chance(0.5)) {  // a cut corner
        const double cx = draw.uniform(0.8, 0.4 * w), cy = draw.uniform(0.8, 0.4 * d);
        room.corners = {{0, 0}, {w - cx, 0}, {w, cy}, {w, d}, {0, d}};
      } else {  // a skewed side: the right wall leans 8-25 degrees
        const double lean = draw.uniform(8, 25) * kDegree * (draw.chance(0.5) ? 1 : -1);
        room.corners = {{0, 0}, {w, 0}, {w + d * std::tan(lean), d}, {0, d}};
      }
      place_scanner(room, draw, 0.9);
      break;
    }
    case RoomCategory::Furniture: {
      room = rectangle(draw, w, d);
      const int wardrobe_side = draw.integer(0, 3);
      const double top = room.ceiling - draw.uniform(0.2, 0.6);
      add_tall_furniture(room, draw, w, d, wardrobe_side, draw.uniform(0.55, 0.65), std::min(top, 2.2),
                         draw.chance(0.5));
      add_tall_furniture(room, draw, w, d, (wardrobe_side + draw.integer(1, 3)) % 4, draw.uniform(0.3, 0.4),
                         std::min(top, draw.uniform(1.7, 2.1)), false);
      add_low_furniture(room, draw, w, d, draw.integer(0, 2));
      place_scanner(room, draw, 0.9);
      break;
    }
    case RoomCategory::NearWall: {
      room = rectangle(draw, w, d);
      const double x = draw.uniform(0.5, 0.8), y = draw.uniform(0.5, 0.8);
      const int corner = draw.integer(0, 3);
      const Eigen::Vector2d spot(corner % 2 == 0 ? x : w - x, corner < 2 ? y : d - y);
      room.scanner = Eigen::Vector3d(spot.x(), spot.y(), draw.uniform(0.9, 1.5));
      break;
    }
    case RoomCategory::Closet: {
      room = rectangle(draw, draw.uniform(1.2, 2.2), draw.uniform(1.2, 2.2));
      room.ceiling = draw.uniform(2.4, 2.7);
      if (draw.chance(0.5)) add_doors(room, draw, 1);
      place_scanner(room, draw, 0.5);
      room.scanner.z() = draw.uniform(1.0, 1.5);
      break;
    }
    case RoomCategory::Mixed: {
      room = notched_rectangle(draw, w, d, draw.uniform(0.8, 1.5), draw.uniform(0.3, 0.8));
      add_doors(room, draw, draw.integer(1, 2));
      add_tall_furniture(room, draw, w, d, draw.integer(1, 3), draw.uniform(0.55, 0.65),
                         std::min(room.ceiling - 0.3, 2.1), draw.chance(0.5));
      place_scanner(room, draw, 0.9);
      break;
    }
    case RoomCategory::BuiltIn: {
      // Its side towards the near corner and the gap behind it are hidden from most spots: the
      // front must not be taken for an L's inner wall meeting the side wall. (Drawn one by one:
      // the order of a call's arguments is the compiler's.)
      const double gap = draw.uniform(0.2, 0.8), depth = draw.uniform(0.8, 1.4), width = draw.uniform(0.8, 1.8);
      room = notched_rectangle(draw, w, d, width, -depth, gap);
      place_scanner(room, draw, 0.9);
      break;
    }
  }
  room.name = std::string(category_name(category));
  room.validate();
  return room;
}

}  // namespace

const std::vector<RoomCategory>& room_categories() {
  static const std::vector<RoomCategory> all = {
      RoomCategory::Box,           RoomCategory::Doors,    RoomCategory::Windows, RoomCategory::Alcove,
      RoomCategory::ChimneyBreast, RoomCategory::LShape,   RoomCategory::TShape,  RoomCategory::Angled,
      RoomCategory::Furniture,     RoomCategory::NearWall, RoomCategory::Closet,  RoomCategory::Mixed,
      RoomCategory::BuiltIn};
  return all;
}

const char* category_name(RoomCategory category) {
  switch (category) {
    case RoomCategory::Box:
      return "box";
    case RoomCategory::Doors:
      return "doors";
    case RoomCategory::Windows:
      return "windows";
    case RoomCategory::Alcove:
      return "alcove";
    case RoomCategory::ChimneyBreast:
      return "chimney_breast";
    case RoomCategory::LShape:
      return "l_shape";
    case RoomCategory::TShape:
      return "t_shape";
    case RoomCategory::Angled:
      return "angled";
    case RoomCategory::Furniture:
      return "furniture";
    case RoomCategory::NearWall:
      return "near_wall";
    case RoomCategory::Closet:
      return "closet";
    case RoomCategory::Mixed:
      return "mixed";
    case RoomCategory::BuiltIn:
      return "built_in";
  }
  return "unknown";
}

RoomCategory category_named(const std::string& name) {
  for (auto category : room_categories())
    if (name == category_name(category)) return category;
  throw std::invalid_argument("no room category called '" + name + "'");
}

HardwareSettings draw_hardware(std::mt19937& random) {
  auto uniform = [&](double low, double high) { return std::uniform_real_distribution<double>(low, high)(random); };
  HardwareSettings h;
  // Range noise grows with range: 2.12 cm at 1.5 m and 3.51 cm at 3 m measured for the
  // LIDAR-Lite v3 (the thesis's reference [2]); each unit a little better or worse.
  const double scale = uniform(0.7, 1.3);
  h.range_noise = 0.0073 * scale;
  h.errors.range_noise_per_m = 0.0093 * scale;
  h.errors.range_bias = uniform(-0.01, 0.01);  // after the user's offset calibration
  h.errors.lever_arm = uniform(0.01, 0.03);    // LiDAR housing on the servo horn
  h.errors.encoder_offset = uniform(-M_PI, M_PI);
  h.errors.yaw_eccentricity = uniform(0, 0.3) * kDegree;  // printed gears
  h.errors.yaw_phase = uniform(0, 2 * M_PI);
  h.errors.servo_offset = uniform(-0.5, 0.5) * kDegree;
  h.errors.servo_error = 0.3 * kDegree;  // a standard servo's deadband and pot nonlinearity
  h.dropout = uniform(0.001, 0.01);
  h.seed = static_cast<unsigned>(random());
  return h;
}

HardwareSettings same_unit(const HardwareSettings& unit, unsigned unit_seed, const HardwareSettings& scan) {
  HardwareSettings h = unit;
  h.errors.encoder_offset = scan.errors.encoder_offset;
  h.errors.yaw_phase = scan.errors.yaw_phase;
  h.seed = scan.seed;
  h.unit_seed = unit_seed;
  return h;
}

GeneratedRoom generate_room(RoomCategory category, unsigned seed) {
  // One stream per (category, seed): adding a category leaves the others' rooms as they were.
  Draw draw(seed * 7919u + static_cast<unsigned>(category) * 104729u + 17u);
  GeneratedRoom generated;
  generated.category = category;
  generated.seed = seed;
  constexpr int kAttempts = 100;  // the stream goes on, so each attempt draws another room
  for (int attempt = 1;; ++attempt) {
    try {
      generated.room = make_room(category, draw);
      break;
    } catch (const NoScannerSpot& error) {
      if (attempt == kAttempts)
        throw std::runtime_error(std::string(category_name(category)) + " room, seed " + std::to_string(seed) + ": " +
                                 error.what() + " in " + std::to_string(kAttempts) + " rooms drawn");
    }
  }
  generated.hardware = draw_hardware(draw.random);
  return generated;
}

std::vector<double> wall_visibility(const RoomModel& room, double min_pitch_deg, double max_pitch_deg) {
  std::vector<double> shares;
  const Eigen::Matrix3d to_scanner = Eigen::AngleAxisd(-room.heading, Eigen::Vector3d::UnitZ()).matrix();
  for (size_t i = 0; i < room.corners.size(); ++i) {
    const Eigen::Vector2d a = room.corners[i], b = room.corners[(i + 1) % room.corners.size()];
    const double length = (b - a).norm();
    const int columns = std::max(1, static_cast<int>(length / 0.05));
    int seen = 0;
    for (int c = 0; c < columns; ++c) {
      const Eigen::Vector2d xy = a + (b - a) * ((c + 0.5) / columns);
      bool visible = false;
      for (double z = 0.05; z < room.ceiling && !visible; z += 0.1) {
        const Eigen::Vector3d offset = Eigen::Vector3d(xy.x(), xy.y(), z) - room.scanner;
        const double pitch = std::acos(offset.z() / offset.norm()) / kDegree;
        if (pitch < min_pitch_deg || pitch > max_pitch_deg) continue;
        const auto hit = room.cast(to_scanner * offset.normalized());
        visible = hit && std::abs(*hit - offset.norm()) < 0.02;
      }
      seen += visible;
    }
    shares.push_back(static_cast<double>(seen) / columns);
  }
  return shares;
}

}  // namespace scanbus::sim
