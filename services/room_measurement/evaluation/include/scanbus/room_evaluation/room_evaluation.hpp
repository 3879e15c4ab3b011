// The room measurement judged on a sweep of generated rooms (sim::generate_room): each room
// scanned through the firmware simulator, measured, and compared with its truth. A room is
// measurable when the scanner sees every one of its walls; a measurable room should be
// measured, any other refused.
#pragma once

#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scanbus/room_measurement/device_calibration.hpp"
#include "scanbus/room_measurement/room_measurement.hpp"
#include "scanbus/sim/room_generator.hpp"

namespace scanbus::room_evaluation {

struct WallCheck {
  double true_length = 0, length = 0, sigma = 0;  // m
  size_t true_wall = 0;                           // the room's wall it was matched to
  double error() const { return length - true_length; }
};

// A true opening (door, window) of a matched wall, and the measured opening that covers most
// of it, both along the true wall from its first corner.
struct OpeningCheck {
  double true_from = 0, true_to = 0;  // m
  bool found = false;                 // a measured opening covers at least half of it
  double from = 0, to = 0;            // m, the measured one
  double edge_error() const { return std::max(std::abs(from - true_from), std::abs(to - true_to)); }
};

enum class Verdict {
  Measured,        // ok, every wall matched to a true one, every wall seen
  Inferred,        // ok, every wall matched to a true one, some not seen but inferred (and said so)
  Wrong,           // ok, but the walls do not match the room's (count or place)
  Refused,         // not ok, and the room could not be measured
  RefusedWrongly,  // not ok, though every wall was in view
};
const char* verdict_name(Verdict verdict);

struct RoomCase {
  sim::RoomCategory category = sim::RoomCategory::Box;
  unsigned seed = 0;
  size_t true_walls = 0;
  bool measurable = false;  // every wall seen (sim::wall_visibility)
  std::string unseen;       // which walls are not, when not measurable
  room_measurement::RoomStatus status = room_measurement::RoomStatus::Ok;
  std::string message;
  Verdict verdict = Verdict::Refused;
  std::vector<WallCheck> walls;                      // matched walls, when measured
  std::vector<double> corner_errors, corner_sigmas;  // m: each corner's distance from the true one, its sigma
  std::vector<OpeningCheck> openings;                // the matched walls' true openings
  size_t spurious_openings = 0;                      // measured openings over no true one
  double true_area = 0, area = 0, area_sigma = 0;
  std::optional<double> true_ceiling_height, ceiling_height;
  size_t points = 0;
  double elapsed_ms = 0;
  std::vector<Eigen::Vector3f> cloud;        // the scan, when SweepOptions::keep_clouds
  sim::RoomModel room;                       // the true room, with it
  room_measurement::RoomResult measurement;  // the whole result, for its plan

  double max_wall_error() const;  // m, absolute; 0 without matched walls
};

// Scans and measures one generated room.
RoomCase evaluate_room(const sim::GeneratedRoom& room, const room_measurement::RoomSettings& settings,
                       bool keep_cloud = false);

struct SweepOptions {
  int count = 120;  // rooms, spread evenly over the categories
  unsigned first_seed = 1;
  std::vector<sim::RoomCategory> categories = sim::room_categories();  // each once; none is an error
  int threads = 0;                                                     // 0: one per core
  bool keep_clouds = false;   // keep each room's scan in its RoomCase (to write it out)
  bool ideal_device = false;  // scan with the device the thesis's equations assume (2 cm noise, no
                              // imperfections): tells the room's geometry from the device's errors
  unsigned unit_seed = 0;     // one unit scans every room (its errors drawn from this seed, each scan
                              // its own power-up: sim::same_unit), as a user's own device; 0: a new
                              // device per room
};

// Every room of the sweep, in category-then-seed order; `progress(done, total)` after each.
std::vector<RoomCase> evaluate_sweep(const SweepOptions& options, const room_measurement::RoomSettings& settings,
                                     const std::function<void(size_t, size_t)>& progress = {});

// A unit calibrated from its scans of a sweep (room_measurement::calibrate_unit over the rooms
// measured with the right walls), beside what the simulator gave it: range bias and lever arm
// (m) and servo offset (rad), as corrections (what the adjustment estimates).
struct SweepCalibration {
  room_measurement::UnitCalibration calibration;
  double true_range_bias = 0, true_lever_arm = 0, true_pitch_offset = 0;
};
SweepCalibration calibrate_on(const std::vector<RoomCase>& cases, unsigned unit_seed);
// The simulated unit `--unit-seed` scans with: its errors, as the simulator draws them.
sim::HardwareSettings unit_of(unsigned unit_seed);

struct SweepSummary {
  std::string category;  // "all" for the whole sweep
  size_t rooms = 0, measurable = 0;
  size_t measured = 0, inferred = 0, wrong = 0, refused = 0, refused_wrongly = 0;
  size_t within_target = 0;  // measured (every wall seen) with every wall within 1 cm and the area within 0.5 %
  size_t ok_over_2cm = 0;    // status ok with a wall more than 2 cm wrong (or wrong walls)
  size_t walls = 0;          // matched walls of measured and inferred rooms
  double max_wall_error = 0, p95_wall_error = 0, median_wall_error = 0;  // m, absolute
  double max_area_error = 0, p95_area_error = 0;                         // relative
  double within_1_sigma = 0, within_2_sigma = 0;                         // shares of matched walls
  size_t corners = 0;                                                    // of measured and inferred rooms
  double median_corner_error = 0, max_corner_error = 0;                  // m
  double corners_within_1_sigma = 0, corners_within_2_sigma = 0;
  size_t true_openings = 0, openings_found = 0, spurious_openings = 0;  // on matched walls
  double median_opening_error = 0, max_opening_error = 0;               // m: the found openings' worse end
  std::optional<double> worst_ceiling_error;                            // m, over rooms that report a ceiling height
};

// Per category (in room_categories() order), then "all".
std::vector<SweepSummary> summarize(const std::vector<RoomCase>& cases);

}  // namespace scanbus::room_evaluation
