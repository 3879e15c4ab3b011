// A room to scan: a floor plan polygon of vertical walls (with openings such as doors),
// a floor and a ceiling (planes that go on past the doors), and boxes as furniture. Room
// coordinates in metres, floor at z = 0; the scanner stands somewhere inside, turned by
// `heading` against the room's axes. Ray casting gives what a LiDAR would measure.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace scanbus::sim {

struct Opening {
  size_t wall = 0;               // wall i runs from corner i to corner i + 1
  double from = 0, to = 0;       // m along the wall from its first corner
  double bottom = 0, top = 2.0;  // m above the floor
};

// A floor-to-ceiling wall outside the room, seen through its openings: a corridor's far
// side, the next room's wall.
struct OutsideWall {
  Eigen::Vector2d from, to;
};

struct Box {
  Eigen::Vector3d min, max;  // axis-aligned in room coordinates
};

struct RoomModel {
  std::string name;
  std::vector<Eigen::Vector2d> corners;  // counter-clockwise
  double ceiling = 2.5;                  // m above the floor
  double outside = 3.0;                  // m: floor and ceiling go on this far past the walls (a corridor)
  std::vector<Opening> openings;
  std::vector<OutsideWall> outside_walls;
  std::vector<Box> boxes;
  Eigen::Vector3d scanner{0, 0, 1.2};  // scanner origin in room coordinates
  double heading = 0;                  // rad, scanner x axis against the room's x axis

  // Distance from an origin along a unit direction, both in the scanner frame; nullopt when
  // the ray escapes.
  std::optional<double> cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;
  std::optional<double> cast(const Eigen::Vector3d& direction) const {
    return cast(Eigen::Vector3d::Zero(), direction);
  }
  // Distance from a point in the scanner frame to the nearest surface.
  double distance_to_surface(const Eigen::Vector3d& point) const;

  // Whether floor and ceiling exist at this point: within `outside` of the floor plan's box.
  bool within_reach(const Eigen::Vector2d& point) const;
  std::vector<double> wall_lengths() const;
  double floor_area() const;
  Eigen::Vector3d to_room(const Eigen::Vector3d& scanner_point) const;

  // Throws std::invalid_argument naming the problem (fewer than 3 corners, scanner outside
  // the floor plan or not between floor and ceiling, an opening off its wall).
  void validate() const;
};

}  // namespace scanbus::sim
