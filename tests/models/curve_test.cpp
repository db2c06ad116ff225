#include "models/cell/curve.hpp"
#include "models/cell/flat_curve.hpp"
#include "tests/bits_of.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
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


// The remembered segment never changes the index: pointAbove with a hint (hit, miss,
// stale, garbage) gives pointAbove's own, for random walks and jumps over tables of
// 2..40 points.
// A NaN is neither below the first point nor above the last: the search must still name a
// segment inside the table (upper_bound alone gives n, and the interpolation read xs[n]).
TEST(Curve, PointAboveOfNanStaysInsideTheTable) {
  for (size_t n : {2u, 3u, 16u, 17u, 40u}) {
    std::vector<double> xs(n);
    for (size_t i = 0; i < n; ++i) xs[i] = static_cast<double>(i);
    const size_t i = pointAbove(xs.data(), n, NAN);
    EXPECT_GE(i, 1u) << n << " points";
    EXPECT_LE(i, n - 1) << n << " points";
    EXPECT_TRUE(std::isnan(interpolateN(xs.data(), xs.data(), n, NAN))) << n << " points";
  }
}

TEST(Curve, PointAboveWithAHintIsPointAbove) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  long hits = 0, checked = 0;
  for (size_t n = 2; n <= 40; ++n) {
    std::vector<double> xs(n);
    for (size_t i = 0; i < n; ++i) xs[i] = -1.0 + 0.37 * static_cast<double>(i) + 0.01 * static_cast<double>(i * i);
    const double lo = xs.front(), span = xs.back() - xs.front();
    SegmentHint hint;
    double x = lo + 0.5 * span;
    for (int k = 0; k < 400; ++k) {
      // Mostly small steps (a cell's SOC), now and then a jump, a table point exactly, or a
      // hint that is garbage.
      const double r = u(rng);
      if (r < 0.1) x = lo + span * u(rng);
      else if (r < 0.15) x = xs[1 + static_cast<size_t>(u(rng) * static_cast<double>(n - 2))];
      else x += (u(rng) - 0.5) * 0.02 * span;
      if (r > 0.97) hint.i = static_cast<uint32_t>(u(rng) * 100.0);
      if (!(x > lo && x < xs.back())) x = lo + 0.5 * span;
      const uint32_t before = hint.i;
      const size_t got = pointAbove(xs.data(), n, x, &hint);
      ASSERT_EQ(got, pointAbove(xs.data(), n, x)) << "n = " << n << ", x = " << x;
      ASSERT_EQ(hint.i, got);
      hits += before == got;
      ++checked;
    }
  }
  EXPECT_GT(hits, checked / 2);  // the walks mostly stay in their segment
}

using test::bitsOf;

// FlatCurve::eval is Curve::eval to the bit, for every kind and axis, with and without an
// Arrhenius factor, inside, at and beyond the table ends and the 2-D grid, with one hint
// carried through a random walk (hits, misses, jumps), compared with == on the bits.
TEST(Curve, FlatCurveIsCurveEvalBitForBit) {
  std::vector<double> long_x, long_y;  // > 16 points: the binary search
  for (int i = 0; i < 30; ++i) {
    long_x.push_back(-0.1 + 0.04 * i + 0.0005 * i * i);
    long_y.push_back(3.0 + 0.05 * i - 0.001 * i * i);
  }
  const std::vector<double> xs = {0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  const std::vector<double> ys = {3.27, 3.61, 3.69, 3.73, 3.77, 3.79, 3.82, 3.87, 3.93, 4.00, 4.08, 4.19};
  const std::vector<double> ah = {-0.03, 0.0, 0.3, 0.6, 0.9, 1.2, 1.372, 1.65, 1.933, 2.2, 2.5, 2.7, 2.85, 3.0, 3.1, 3.25};
  const std::vector<double> ah_y = {4.2, 4.18, 4.06, 3.96, 3.86, 3.715, 3.661, 3.6, 3.558, 3.51, 3.43, 3.33, 3.18, 2.95, 2.6, 1.8};
  const std::vector<double> temps = {-10.0, 0.0, 25.0, 45.0};
  std::vector<std::vector<double>> rows;
  for (size_t j = 0; j < temps.size(); ++j) {
    std::vector<double> row;
    for (size_t i = 0; i < xs.size(); ++i) row.push_back(0.02 + 0.01 * static_cast<double>(j) - 0.005 * xs[i]);
    rows.push_back(row);
  }
  const std::vector<Curve> curves = {
      Curve::constant(3.7),
      Curve::constant(0.01).withArrhenius(2000.0, 25.0),
      Curve::polynomial(kRint, CurveAxis::Discharged_Ah),
      Curve::polynomial(kRint, CurveAxis::Discharged_Ah).withArrhenius(2250.0, 20.0),
      Curve::polynomial({0.8, 3.4}),
      // FlatCurve's Horner is unrolled up to eight coefficients, a loop past them: every
      // count from one to eight, and nine
      Curve::polynomial({0.0123}),
      Curve::polynomial({-0.2, 3.7, 0.0123}),
      Curve::polynomial({-0.457, 0.1991, 0.0695, 3.1}),
      Curve::polynomial({0.4481, -0.457, 0.1991, 0.0695, 3.3}),
      Curve::polynomial({-0.1914, 0.4481, -0.457, 0.1991, 0.0695, 3.3, -1e-3}, CurveAxis::Discharged_Ah),
      Curve::polynomial({0.0292, -0.1914, 0.4481, -0.457, 0.1991, 0.0695, 3.3, -1e-3}).withArrhenius(1800.0, 25.0),
      Curve::polynomial({1e-3, -0.02, 0.0292, -0.1914, 0.4481, -0.457, 0.1991, 0.0695, 3.3}, CurveAxis::Discharged_Ah),
      Curve::table(xs, ys),
      Curve::table(xs, ys).withArrhenius(-1500.0, 30.0),
      Curve::table(ah, ah_y, CurveAxis::Discharged_Ah),
      Curve::table(long_x, long_y),
      Curve::table({0.0, 1.0}, {0.02, 0.01}),
      Curve::table2d(xs, temps, rows),
      Curve::table2d(xs, {25.0}, {rows[0]}),
      Curve::table2d(ah, temps, {ah_y, ah_y, ah_y, ah_y}, CurveAxis::Discharged_Ah),
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  long checked = 0;
  for (size_t k = 0; k < curves.size(); ++k) {
    const Curve& c = curves[k];
    const FlatCurve f = FlatCurve::of(c);
    CurveHint hint;
    double soc = 0.5, t_C = 25.0;
    std::vector<double> probes_soc = {0.0, 1.0, -0.2, 1.3, -1e-300, 1.0 + 1e-15};
    for (double x : xs) probes_soc.push_back(x);  // the SOC tables' points exactly
    for (double x : ah) probes_soc.push_back(1.0 - x / 3.1);
    const std::vector<double> probes_t = {-40.0, -10.0, 0.0, 25.0, 45.0, 80.0, 12.5, -273.0};
    for (int n = 0; n < 3000; ++n) {
      const double r = u(rng);
      if (r < 0.05) soc = probes_soc[static_cast<size_t>(u(rng) * static_cast<double>(probes_soc.size()))];
      else if (r < 0.15) soc = -0.3 + 1.6 * u(rng);
      else soc += (u(rng) - 0.5) * 0.01;
      if (u(rng) < 0.1) t_C = probes_t[static_cast<size_t>(u(rng) * static_cast<double>(probes_t.size()))];
      else t_C += (u(rng) - 0.5);
      const double q = u(rng) < 0.5 ? 3.1 : 5.0;
      ASSERT_EQ(bitsOf(f.eval(soc, q, t_C, hint)), bitsOf(c.eval(soc, q, t_C)))
          << "curve " << k << ", soc " << soc << ", T " << t_C;
      ++checked;
    }
    // Without a temperature (Curve::eval's reference) and at a NaN SOC (every table, short
    // or long, stays on its last segment).
    ASSERT_EQ(bitsOf(f.eval(0.37, 3.1, kReferenceTemp_C, hint)), bitsOf(c.eval(0.37, 3.1))) << "curve " << k;
    ASSERT_EQ(bitsOf(f.eval(NAN, 3.1, 25.0, hint)), bitsOf(c.eval(NAN, 3.1, 25.0))) << "curve " << k;
  }
  EXPECT_EQ(checked, 3000L * static_cast<long>(curves.size()));
}

}  // namespace
}  // namespace packsim
