// The thermal network's steady state against a direct linear solve.
#include "models/thermal/thermal_network.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace packsim {
namespace {

TEST(ThermalNetwork, ChainConservesHeatFlow) {
  ThermalNetwork n;
  for (int i = 0; i < 3; ++i) n.addNode("cell", 10.0, 0.1);
  n.link(0, 1, 0.5);
  n.link(1, 2, 0.5);
  const double T[3] = {30.0, 40.0, 20.0}, q[3] = {1.0, 2.0, 0.0};
  double dT[3];
  n.derivatives(T, q, 25.0, 25.0, dT);
  // Σ C·dT/dt = Σ q - Σ G_amb (T - T_amb): links move heat, never create it.
  double lhs = 0.0, rhs = 0.0;
  for (int i = 0; i < 3; ++i) {
    lhs += 10.0 * dT[i];
    rhs += q[i] - 0.1 * (T[i] - 25.0);
  }
  EXPECT_NEAR(lhs, rhs, 1e-12);
  EXPECT_NEAR(dT[0] * 10.0, 1.0 - 0.1 * 5.0 - 0.5 * (30.0 - 40.0), 1e-12);
}

TEST(ThermalNetwork, CoolantIsASecondBoundary) {
  ThermalNetwork n;
  n.addNode("cell", 10.0, 0.1, 0.4);
  const double T[1] = {30.0}, q[1] = {0.0};
  double dT[1];
  n.derivatives(T, q, 25.0, 15.0, dT);
  EXPECT_NEAR(dT[0], (-0.1 * 5.0 - 0.4 * 15.0) / 10.0, 1e-12);
}

}  // namespace
}  // namespace packsim
