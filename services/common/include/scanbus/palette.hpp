// Colours shared by the coloured clouds on the bus (RViz, Foxglove) and the pictures, so a
// wall or a height has the same colour in both: 0xRRGGBB. No DDS, no drawing library.
#pragma once

#include <cstddef>
#include <cstdint>

namespace scanbus {

// A colour for a height, from blue (low) through green to red (high), as the MAV paper's
// figures colour their clouds.
uint32_t height_colour(double z, double low, double high);

// A distinct colour for wall `index` (ten, then they repeat).
uint32_t wall_colour(size_t index);

}  // namespace scanbus
