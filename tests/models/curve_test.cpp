#include "models/cell/curve.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

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

// pointAbove scans short tables and bisects long ones: both must give std::upper_bound's
// index, so a table reads the same whichever way it is searched. Tables of 2..40 points
// (both sides of the switch at 16), x at every point, between points and just beside them.
TEST(Curve, PointAboveIsTheUpperBoundForShortAndLongTables) {
  long checked = 0;
  for (size_t n = 2; n <= 40; ++n) {
    std::vector<double> xs(n);
    for (size_t i = 0; i < n; ++i) xs[i] = -1.0 + 0.37 * static_cast<double>(i) + 0.01 * static_cast<double>(i * i);
    std::vector<double> probes;
    for (size_t i = 0; i < n; ++i) {
      probes.push_back(xs[i]);
      probes.push_back(std::nextafter(xs[i], -INFINITY));
      probes.push_back(std::nextafter(xs[i], INFINITY));
      if (i + 1 < n) probes.push_back(0.5 * (xs[i] + xs[i + 1]));
    }
    for (double x : probes) {
      if (!(x > xs.front() && x < xs.back())) continue;  // its domain: strictly inside the table
      const size_t want = static_cast<size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin());
      ASSERT_EQ(pointAbove(xs.data(), n, x), want) << "n = " << n << ", x = " << x;
      ++checked;
    }
  }
  EXPECT_GT(checked, 2000);
}

}  // namespace
}  // namespace packsim
