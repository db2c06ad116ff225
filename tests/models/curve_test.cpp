#include "models/cell/curve.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace packsim {
namespace {

// reference system C: Rint(x) with x = capacity discharged in Ah, highest power first.
const std::vector<double> kRint = {0.0292, -0.1914, 0.4481, -0.457, 0.1991, 0.0695};

TEST(Curve, PolynomialHighestPowerFirst) {
  const Curve c = Curve::polynomial(kRint, CurveAxis::Discharged_Ah);
  EXPECT_DOUBLE_EQ(c.eval(1.0, 3.1), 0.0695);  // full cell: nothing discharged
  const double x = 1.55;                       // half of 3.1 Ah discharged
  const double expect = 0.0292 * std::pow(x, 5) - 0.1914 * std::pow(x, 4) + 0.4481 * std::pow(x, 3) -
                        0.457 * x * x + 0.1991 * x + 0.0695;
  EXPECT_NEAR(c.eval(0.5, 3.1), expect, 1e-15);
}

TEST(Curve, TableInterpolatesAndHoldsEnds) {
  const Curve c = Curve::table({0.0, 0.5, 1.0}, {3.0, 3.7, 4.2});
  EXPECT_DOUBLE_EQ(c.eval(0.25, 1.0), 3.35);
  EXPECT_DOUBLE_EQ(c.eval(0.75, 1.0), 3.95);
  EXPECT_DOUBLE_EQ(c.eval(-0.1, 1.0), 3.0);
  EXPECT_DOUBLE_EQ(c.eval(1.2, 1.0), 4.2);
}

TEST(Curve, RejectsNonIncreasingTable) {
  EXPECT_THROW(Curve::table({0.0, 0.5, 0.5}, {1, 2, 3}), std::invalid_argument);
}

}  // namespace
}  // namespace packsim
