// Bytes of a scanned room's cloud (x y z rgb float32, 16 bytes a point): rays from the
// scanner at (2, 1.5, 1.2) to the walls, floor and ceiling of a 4 x 3 x 2.5 m room with
// 2 cm range noise, coloured by height. Compresses like real scans, unlike random bytes.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace scanbus::bench {

inline std::vector<uint8_t> room_cloud_points(uint32_t points, uint32_t seed) {
  std::mt19937 random(seed);
  std::normal_distribution<float> noise(0.0f, 0.02f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float origin[3] = {2.0f, 1.5f, 1.2f}, size[3] = {4.0f, 3.0f, 2.5f};
  std::vector<uint8_t> bytes(16ull * points);
  for (uint32_t i = 0; i < points; ++i) {
    const float yaw = 2 * static_cast<float>(M_PI) * unit(random);
    const float pitch = static_cast<float>(M_PI) * (unit(random) - 0.5f);
    const float d[3] = {std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch)};
    float range = 1e9f;
    for (int axis = 0; axis < 3; ++axis) {
      if (std::abs(d[axis]) < 1e-6f) continue;
      const float wall = d[axis] > 0 ? size[axis] : 0.0f;
      range = std::min(range, (wall - origin[axis]) / d[axis]);
    }
    range += noise(random);
    float point[4] = {origin[0] + d[0] * range, origin[1] + d[1] * range, origin[2] + d[2] * range, 0.0f};
    const auto level = static_cast<uint32_t>(std::clamp(point[2] / size[2], 0.0f, 1.0f) * 255);
    const uint32_t rgb = (level << 16) | (255 - level);
    std::memcpy(&point[3], &rgb, 4);
    std::memcpy(bytes.data() + 16ull * i, point, 16);
  }
  return bytes;
}

}  // namespace scanbus::bench
