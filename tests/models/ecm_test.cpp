#include "models/cell/ecm.hpp"

#include <gtest/gtest.h>

namespace packsim {
namespace {

CellParams cell() {
  CellParams p;
  p.capacity_Ah = 2.0;
  p.ocv_V = Curve::polynomial({0.8, 3.4});  // 3.4 + 0.8·soc
  p.r0_ohm = Curve::constant(0.02);
  p.rc = {{0.01, 1000.0}};
  p.coulombic_efficiency = 0.98;
  return p;
}

TEST(Ecm, DerivativesFollowTheEquations) {
  const CellParams p = cell();
  const double x[2] = {0.5, 0.004};
  double dx[2];
  ecm::derivatives(p, x, 3.0, dx);
  EXPECT_DOUBLE_EQ(dx[0], -3.0 / (3600.0 * 2.0));
  EXPECT_DOUBLE_EQ(dx[1], 3.0 / 1000.0 - 0.004 / 10.0);
  ecm::derivatives(p, x, -3.0, dx);  // charging: coulombic efficiency applies
  EXPECT_DOUBLE_EQ(dx[0], 0.98 * 3.0 / (3600.0 * 2.0));
}

TEST(Ecm, TerminalVoltageAndHeat) {
  const CellParams p = cell();
  const double x[2] = {0.5, 0.004};
  EXPECT_DOUBLE_EQ(ecm::terminalVoltage(p, x, 3.0), 3.8 - 0.004 - 3.0 * 0.02);
  EXPECT_DOUBLE_EQ(ecm::heat_W(p, x, 3.0), 9.0 * 0.02 + 0.004 * 0.004 / 0.01);
}

}  // namespace
}  // namespace packsim
