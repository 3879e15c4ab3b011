// The room thesis's automated dimension calculation (Algorithms 1 to 3), for rooms of any
// simple polygon of vertical walls: filter, find planes, pick and order the room's walls,
// intersect them, measure. Input in metres in the scanner frame (scanner at the origin).
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "scanbus/config.hpp"
#include "scanbus/room_measurement/histogram_filter.hpp"
#include "scanbus/room_measurement/planes.hpp"
#include "scanbus/room_measurement/wall_adjustment.hpp"
#include "scanbus/room_measurement/walls.hpp"

namespace scanbus::room_measurement {

struct RoomSettings {
  HistogramFilterSettings histogram;
  size_t density_reference = 18560;  // points for which histogram.min_points holds (the thesis's
                                     // scan); larger clouds scale it up; 0 keeps it absolute
  double voxel_leaf = 0.05;          // m; 0 skips the VoxelGrid
  RansacSettings ransac;
  double min_plane_share = 0.02;     // vertical planes with fewer of the filtered points are clutter
  double min_wall_height = 1.2;      // m of height a plane's inliers must span to be a wall
  double min_wall_coverage = 0.5;    // and the share of that height they must fill (floor and ceiling
                                     // points left in one vertical slice span it but fill only its ends)
  double max_wall_height_gap = 0.8;  // m of height with no inlier: a ceiling beam lined up with
                                     // furniture below it is two surfaces, not a wall (a wall is seen
                                     // at every height somewhere along it)
  double min_wall_fill = 0.3;        // and of their length: RANSAC also fits planes through scattered
                                     // clutter that happens to line up (walls hidden in part by tall
                                     // furniture keep less than half, so not more)
  double open_sector_deg = 10;       // degrees: a wider sector where no wall encloses the scanner is searched
                                     // again among its own points (a far or glass wall's few returns make no
                                     // plane of min_plane_share of the whole cloud); narrower ones hold too
                                     // few points to tell a wall from clutter (4 let in clutter on the
                                     // development rooms, 20 found fewer walls: docs/room_evaluation.md)
  PolygonSettings polygon;
  AdjustmentSettings adjustment;
  double opening_min_width = 0.3;         // m: narrower gaps with returns beyond are not doors or windows
  double opening_beyond = 0.2;            // m past the wall's line a return must lie to be seen through it
  double recess_depth = 0.9;              // m: a surface seen through an opening nearer than this behind the
                                          // wall is a recess, not a corridor (a hallway is at least 0.9 m wide)
  double beam_divergence = 0.008;         // rad: LIDAR-Lite v3's beam (its spec, 8 mrad); half its footprint
                                          // blurs where a wall's points end at a corner the scanner sees
  size_t max_horizontal_samples = 50000;  // floor and ceiling are found on a subsample
};

// The `room_measurement` config section (keys documented in config/services/room_measurement.yaml).
RoomSettings room_settings_from_config(const Config& section);

// Values as in RoomMeasurement_Constants.
enum class RoomStatus : uint8_t { Ok = 0, TooFewPoints = 1, TooFewWalls = 2, WallsDoNotClose = 3, InputError = 4 };
const char* status_name(RoomStatus status);

struct MeasuredWall {
  WallLine line;
  size_t points = 0;              // inliers of the final fit
  size_t candidate = 0;           // the candidate line it was refined from: walls sharing one are one
                                  // wall of the room broken by a chimney breast or a T's stem
  double length = 0;              // m, corner to corner
  double length_sigma = 0;        // m, one sigma (the wall adjustment's, else the offsets' standard errors)
  std::vector<Opening> openings;  // doors and windows seen through, along the wall from corners[i]
  bool inferred() const { return line.inferred; }  // not seen (walls.hpp, infer_hidden_wall)
};

// The scanner's own errors as the wall adjustment estimated them (wall_adjustment.hpp): what a
// user checks the device's calibration against.
struct DeviceEstimate {
  enum class State { NotEstimated, Applied, Held };
  State state = State::NotEstimated;       // Held: beyond 3 sigmas of their priors, not applied (the walls
                                           // fitted alone); the terms say what the fit wanted
  double range_bias = 0, lever_arm = 0;    // m
  double pitch_offset = 0, yaw_error = 0;  // rad; yaw_error the once-per-turn amplitude
  // What this scan's points alone say about the unit's range bias, lever arm and pitch offset
  // (AdjustedWalls::unit_information): what a calibration pools (device_calibration.hpp).
  Eigen::Matrix3d unit_information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d unit_rhs = Eigen::Vector3d::Zero();
  std::vector<StepLeak> unit_step_leaks{};  // the servo steps' part of unit_rhs (AdjustedWalls')
};
const char* device_state_name(DeviceEstimate::State state);

struct RoomResult {
  RoomStatus status = RoomStatus::Ok;
  std::string message;
  std::vector<MeasuredWall> walls;       // in order around the room
  std::vector<WallLine> candidates;      // every wall-like plane found, for diagnosis when no room closes
  std::vector<Eigen::Vector2d> corners;  // corners[i] joins walls[i-1] and walls[i]
  std::vector<bool> corner_inferred;     // per corner: placed by assumption, not seen (an inferred wall's far end)
  std::vector<double> corner_sigmas;     // m per corner: one sigma of its distance from the true corner
                                         // (the wall adjustment's; empty without it)
  double area = 0, perimeter = 0;
  double area_sigma = 0;  // m^2, one sigma
  DeviceEstimate device;
  std::optional<double> floor_z, ceiling_z;  // only where seen
  std::string height_note;                   // why there is no ceiling height, when there is none
  size_t points_in = 0, points_valid = 0, points_after_filter = 0, points_after_voxel = 0;
  bool voxel_overflow = false;
  // Section 5.2's diagnostic: distances of the input points near the longest wall to its
  // plane, in bins of error_bin metres up to 10 cm.
  double error_bin = 0.005;
  std::vector<size_t> error_histogram;
  double elapsed_ms = 0;

  std::optional<double> ceiling_height() const {
    if (floor_z && ceiling_z) return *ceiling_z - *floor_z;
    return std::nullopt;
  }
};

RoomResult measure_room(const std::vector<Eigen::Vector3f>& points, const RoomSettings& settings);

}  // namespace scanbus::room_measurement
