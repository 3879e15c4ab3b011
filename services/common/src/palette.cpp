#include "scanbus/palette.hpp"

#include <algorithm>
#include <cmath>

namespace scanbus {

uint32_t height_colour(double z, double low, double high) {
  const double t = high > low ? std::clamp((z - low) / (high - low), 0.0, 1.0) : 0.5;
  // Hue from 240 degrees (blue) down to 0 (red) at full saturation and value.
  const double hue = (1 - t) * 4;  // in sixths of the circle
  const double fraction = hue - std::floor(hue);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(std::floor(hue))) {
    case 0:
      r = 1, g = fraction;
      break;
    case 1:
      r = 1 - fraction, g = 1;
      break;
    case 2:
      g = 1, b = fraction;
      break;
    case 3:
      g = 1 - fraction, b = 1;
      break;
    default:
      b = 1;
  }
  const auto byte = [](double v) { return static_cast<uint32_t>(std::lround(v * 255)); };
  return byte(r) << 16 | byte(g) << 8 | byte(b);
}

uint32_t wall_colour(size_t index) {
  static const uint32_t kPalette[] = {0xE6194B, 0x3CB44B, 0x4363D8, 0xF58231, 0x911EB4,
                                      0x42D4F4, 0xF032E6, 0x9A6324, 0x469990, 0x808000};
  return kPalette[index % (sizeof(kPalette) / sizeof(kPalette[0]))];
}

}  // namespace scanbus
