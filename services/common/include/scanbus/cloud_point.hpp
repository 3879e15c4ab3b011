// A point of a cloud as every core sees it: position in metres and an intensity.
#pragma once

#include <Eigen/Core>

namespace scanbus {

struct CloudPoint {
  Eigen::Vector3f position;
  float intensity = 0;
};

}  // namespace scanbus
