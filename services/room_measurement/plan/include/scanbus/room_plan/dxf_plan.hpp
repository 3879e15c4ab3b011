// The measured room as a DXF drawing a builder opens in a CAD program: walls corner to
// corner with their openings left open, each opening's width, a dimension outside each wall
// (extension lines, dimension line, its length and one-sigma uncertainty), the area. Drawing units are metres, the
// scanner frame's x-y (scanner at the origin). Written with dxflib.
#pragma once

#include <stdexcept>
#include <string>

#include "scanbus/room_measurement/room_measurement.hpp"

namespace scanbus::room_plan {

// Layer names: what a CAD user toggles.
inline constexpr const char* kWallLayer = "WALLS";
inline constexpr const char* kOpeningLayer = "OPENINGS";
inline constexpr const char* kInferredLayer = "INFERRED";  // walls not seen, placed by assumption
inline constexpr const char* kDimensionLayer = "DIMENSIONS";
inline constexpr const char* kTextLayer = "ANNOTATIONS";

struct DxfPlanError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A room that did not close has no corners to draw: its candidate walls go on WALLS as
// their inliers' extents, and the status on ANNOTATIONS. Throws DxfPlanError naming the file
// when it cannot be written.
void write_dxf_plan(const std::string& path, const room_measurement::RoomResult& room, const std::string& title);

}  // namespace scanbus::room_plan
