#include "models/pack/pack.hpp"

#include <gtest/gtest.h>

namespace packsim {
namespace {

Pack group(double r0_second) {
  Pack p;
  p.series = 1;
  p.parallel = 2;
  CellParams c;
  c.ocv_V = Curve::constant(3.7);
  c.r0_ohm = Curve::constant(0.02);
  p.cells = {c, c};
  p.cells[1].r0_ohm = Curve::constant(r0_second);
  return p;
}

// Group 0's split with each cell's EMF and R0 from the ECM at its state.
double split(const Pack& p, double i_A, const double (*x)[1], double* i) {
  double emf[2], r0[2];
  for (int c = 0; c < 2; ++c) {
    emf[c] = ecm::emf(p.cells[c], x[c], ecm::ocv(p.cells[c], x[c][0]));
    r0[c] = ecm::r0(p.cells[c], x[c][0], kReferenceTemp_C, i_A);
  }
  return p.splitGroup(0, i_A, emf, r0, i);
}

TEST(Pack, EqualCellsSplitEqually) {
  const Pack p = group(0.02);
  const double x[2][1] = {{0.5}, {0.5}};
  double i[2];
  const double v = split(p, 10.0, x, i);
  EXPECT_NEAR(i[0], 5.0, 1e-12);
  EXPECT_NEAR(i[1], 5.0, 1e-12);
  EXPECT_DOUBLE_EQ(i[0], i[1]);
  EXPECT_NEAR(v, 3.7 - 5.0 * 0.02, 1e-12);
}

TEST(Pack, DoubleResistanceCarriesOneThird) {
  const Pack p = group(0.04);
  const double x[2][1] = {{0.5}, {0.5}};
  double i[2];
  split(p, 9.0, x, i);
  EXPECT_NEAR(i[0], 6.0, 1e-12);
  EXPECT_NEAR(i[1], 3.0, 1e-12);
  EXPECT_NEAR(i[0] + i[1], 9.0, 1e-14);
}

}  // namespace
}  // namespace packsim
