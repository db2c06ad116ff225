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

TEST(Pack, EqualCellsSplitEqually) {
  const Pack p = group(0.02);
  const double x[2][1] = {{0.5}, {0.5}};
  double i[2];
  const double v = p.splitGroup(0, 10.0, [&](int c) { return x[c]; }, i);
  EXPECT_NEAR(i[0], 5.0, 1e-12);
  EXPECT_NEAR(i[1], 5.0, 1e-12);
  EXPECT_DOUBLE_EQ(i[0], i[1]);
  EXPECT_NEAR(v, 3.7 - 5.0 * 0.02, 1e-12);
}

TEST(Pack, DoubleResistanceCarriesOneThird) {
  const Pack p = group(0.04);
  const double x[2][1] = {{0.5}, {0.5}};
  double i[2];
  p.splitGroup(0, 9.0, [&](int c) { return x[c]; }, i);
  EXPECT_NEAR(i[0], 6.0, 1e-12);
  EXPECT_NEAR(i[1], 3.0, 1e-12);
  EXPECT_NEAR(i[0] + i[1], 9.0, 1e-14);
}

}  // namespace
}  // namespace packsim
