// Rooms for an evaluation sweep: each category a kind of room people measure, each seed one
// room of it (sizes, openings, furniture, the scanner's spot and height) and one device with
// its own imperfections. The sweep's rooms come from seeds, never from hand tuning, and the
// distributions model rooms and devices (docs/room_simulation.md), not the measurement.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "scanbus/sim/room_model.hpp"
#include "scanbus/sim/simulated_hardware.hpp"

namespace scanbus::sim {

enum class RoomCategory {
  Box,            // a plain rectangle, low furniture
  Doors,          // open doors onto a corridor or the next room
  Windows,        // windows, with nothing or a far building behind
  Alcove,         // a recess in one wall
  ChimneyBreast,  // a protrusion from one wall
  LShape,
  TShape,
  Angled,     // a wall at an angle other than 90 degrees (a cut corner, a skewed side)
  Furniture,  // a wardrobe and a tall shelf against walls
  NearWall,   // the scanner in a corner, 0.5-0.8 m from two walls
  Closet,     // a small room whose floor may be out of the scanner's view
  Mixed,      // doors, furniture and an alcove together
  BuiltIn,    // a boxed-in stair, shaft or built-in cupboard to the ceiling, deeper than furniture, near a corner
};

const std::vector<RoomCategory>& room_categories();
const char* category_name(RoomCategory category);
// The category called `name` (as category_name gives it); std::invalid_argument for none.
RoomCategory category_named(const std::string& name);

struct GeneratedRoom {
  RoomCategory category = RoomCategory::Box;
  unsigned seed = 0;
  RoomModel room;
  HardwareSettings hardware;  // noise, dropouts and DeviceErrors of this room's device
};

GeneratedRoom generate_room(RoomCategory category, unsigned seed);

// A device as built: imperfections drawn from what such a platform has (a LIDAR-Lite v3 on a
// standard servo on a geared pole).
HardwareSettings draw_hardware(std::mt19937& random);

// One unit (`unit`, drawn by draw_hardware; its servo's errors from `unit_seed`, not 0) in a
// scan whose own draw is `scan`: the unit's range bias, lever arm, servo, gear and noise, the
// scan's power-up (where the encoder counts from, so the gear error's phase) and noise stream.
HardwareSettings same_unit(const HardwareSettings& unit, unsigned unit_seed, const HardwareSettings& scan);

// Share of a wall's length the scanner can see over a height band: columns every 5 cm,
// heights every 10 cm in the pitch range the device sweeps (42-120 degrees from up), a
// column seen when a ray reaches it unblocked. Truth for deciding whether a room can be
// measured at all.
std::vector<double> wall_visibility(const RoomModel& room, double min_pitch_deg = 42, double max_pitch_deg = 120);

}  // namespace scanbus::sim
