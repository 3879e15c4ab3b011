#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scanbus/scanner_io/spherical.hpp"

using namespace scanbus::scanner_io;

TEST(Spherical, AxesFollowTheThesisConvention) {
  EXPECT_TRUE(to_cartesian(2.0, 0.0, M_PI / 2).isApprox(Eigen::Vector3f(2, 0, 0), 1e-6f));
  EXPECT_TRUE(to_cartesian(2.0, M_PI / 2, M_PI / 2).isApprox(Eigen::Vector3f(0, 2, 0), 1e-6f));
  EXPECT_NEAR(to_cartesian(2.0, 1.0, 0.0).z(), 2.0f, 1e-6f);
  EXPECT_NEAR(to_cartesian(1.0, 0.3, 2.0).norm(), 1.0f, 1e-6f);
}

TEST(Spherical, GateDropsNoReturnAndNonFinite) {
  const RangeGate gate;
  SphericalMeasurement measurement;
  measurement.range = 0.0;
  EXPECT_FALSE(in_gate(measurement, gate));
  measurement.range = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(in_gate(measurement, gate));
  measurement.range = 41.0;
  EXPECT_FALSE(in_gate(measurement, gate));
  measurement.range = 3.0;
  EXPECT_TRUE(in_gate(measurement, gate));
}
