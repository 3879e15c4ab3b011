// The ICAO standard atmosphere's pressure-altitude relation (troposphere), what a
// barometric altimeter assumes: the simulator makes pressure with it, the pose estimator
// turns pressure back into altitude.
#pragma once

#include <cmath>

namespace scanbus {

// Pa at an altitude above sea level (m), and back.
inline double pressure_at_altitude(double altitude) { return 101325.0 * std::pow(1 - 2.25577e-5 * altitude, 5.25588); }
inline double altitude_at_pressure(double pressure) {
  return (1 - std::pow(pressure / 101325.0, 1 / 5.25588)) / 2.25577e-5;
}

}  // namespace scanbus
