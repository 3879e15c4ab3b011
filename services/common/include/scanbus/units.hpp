#pragma once
#include <cmath>

namespace scanbus {

// One degree in radians. Angles are radians inside; degrees only at the edges (files, prints).
inline constexpr double kDegree = M_PI / 180;

}  // namespace scanbus
