// The CVODE Jacobian (core/sim/cvode_jacobian.hpp): its pattern from the plant's
// structure and its coloured difference quotients against a dense difference-quotient
// Jacobian (every column perturbed alone, same increments) on a small parallel pack
// with thermal coupling (system D's cell, skin and board nodes at 3s4p).
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>

#include "core/scenario/overrides.hpp"
#include "core/sim/cvode_jacobian.hpp"
#include "core/sim/plant_ode.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario scaled(const std::string& file, int series, int parallel) {
  return loadScenarioFileWithOverrides(test::scenarioDir() + "/" + file,
                                       {{"pack.series", std::to_string(series)},
                                        {"pack.parallel", std::to_string(parallel)},
                                        {"hardware.thermistors.at_groups", "[1, 2]"},
                                        {"hardware.afe.devices_per_board", "1"}});
}

struct PackOde {
  Scenario s;
  Plant plant;
  PlantInputs in;
  PlantOde ode;
  std::vector<double> x;
  PackOde(int series, int parallel, const std::string& file = "motorcycle_110s.yaml")
      : s(scaled(file, series, parallel)), plant(s), ode(plant, s.run, in), x(static_cast<size_t>(ode.size())) {
    in.relay_closed = true;
    in.load.i0_A = 150.0;
    plant.initialState(x.data());
    // Away from the initial state: RC voltages, temperatures and quadratures that differ.
    for (size_t i = 0; i < x.size(); ++i) x[i] += 1e-3 * static_cast<double>(i % 7);
    for (int j = 0; j < plant.thermal().nodeCount(); ++j) x[static_cast<size_t>(plant.tempIndex(j))] += 0.3 * j;
  }
};

// heldCurrent: the dense reference holds the pack current too (a power load couples
// every cell through it; the pattern leaves that out, PlantOde::holdCouplings).
void expectEqualsDense(PackOde& su, bool heldCurrent) {
  PlantOde& ode = su.ode;
  const int n = ode.size();
  const size_t ns = static_cast<size_t>(n);
  std::vector<double> f0(ns), w(ns), x1(ns), f1(ns);
  const std::vector<double> atol = ode.absTolerances();
  for (size_t i = 0; i < ns; ++i) w[i] = 1.0 / (su.s.run.rtol * std::fabs(su.x[i]) + atol[i]);
  ode.rhs(0.0, su.x.data(), f0.data());
  ode.holdCouplings(0.0, su.x.data());
  ode.rhsHeld(0.0, su.x.data(), f1.data());
  for (size_t i = 0; i < ns; ++i) ASSERT_EQ(f1[i], f0[i]) << "held at x0, the right-hand side is the same, state " << i;

  ColouredJacobian jac(ode.jacobianPattern());
  const JacobianPattern& p = jac.pattern();
  std::vector<double> values(static_cast<size_t>(p.nonzeros()));
  jac.fill(ode, 0.0, su.x.data(), f0.data(), w.data(), x1.data(), f1.data(), values.data());
  EXPECT_LT(jac.colourCount(), 4 * su.plant.stride() + 8);  // a group's states plus neighbours and loose columns

  // Dense: each column alone.
  std::vector<double> dense(ns * ns, 0.0);  // column-major
  for (int j = 0; j < n; ++j) {
    x1 = su.x;
    const size_t js = static_cast<size_t>(j);
    const double h = std::sqrt(DBL_EPSILON) * std::max(std::fabs(su.x[js]), 1.0 / w[js]);
    x1[js] += h;
    if (heldCurrent) {
      ode.holdCouplings(0.0, su.x.data());
      ode.rhsHeld(0.0, x1.data(), f1.data());
    } else {
      ode.rhs(0.0, x1.data(), f1.data());
    }
    for (size_t i = 0; i < ns; ++i) dense[js * ns + i] = (f1[i] - f0[i]) / (x1[js] - su.x[js]);
  }
  std::vector<double> rowScale(ns, 0.0);
  for (size_t j = 0; j < ns; ++j)
    for (size_t i = 0; i < ns; ++i) rowScale[i] = std::max(rowScale[i], std::fabs(dense[j * ns + i]));

  std::vector<double> sparse(ns * ns, 0.0);
  std::vector<char> listed(ns * ns, 0);
  for (int j = 0; j < n; ++j)
    for (int k = p.colptr[static_cast<size_t>(j)]; k < p.colptr[static_cast<size_t>(j) + 1]; ++k) {
      const size_t at = static_cast<size_t>(j) * ns + static_cast<size_t>(p.rows[static_cast<size_t>(k)]);
      sparse[at] = values[static_cast<size_t>(k)];
      listed[at] = 1;
    }
  int compared = 0, nonzero = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const size_t at = static_cast<size_t>(j) * ns + static_cast<size_t>(i);
      const double d = dense[at];
      const double scale = rowScale[static_cast<size_t>(i)];
      if (listed[at]) {
        // A listed entry: the coloured value is the dense one.
        EXPECT_NEAR(sparse[at], d, 1e-6 * std::max(std::fabs(d), scale) + 1e-300) << "row " << i << " col " << j;
        ++compared;
        nonzero += d != 0.0;
      } else if (i < p.local || j >= p.local) {
        // Not listed in a complete row, or from a column perturbed alone: truly zero.
        EXPECT_LE(std::fabs(d), 1e-12 * scale) << "row " << i << " col " << j << " depends on an unlisted state";
      }
    }
  EXPECT_GT(compared, 12 * 12 * su.plant.stride());  // at least the group blocks
  EXPECT_GT(nonzero, compared / 2);
}

TEST(SparseJacobian, EqualsDenseDifferenceQuotientsOnAParallelPack) {
  PackOde d(3, 4);  // system D: a current load; pack skin linked to every cell, board nodes
  expectEqualsDense(d, false);
  PackOde b(3, 4, "solar_car_28s15p.yaml");  // system B: a power load; group spread
  expectEqualsDense(b, true);
}

TEST(SparseJacobian, ColoursDoNotGrowWithTheSeriesCount) {
  PackOde small(3, 4), large(40, 4);
  const ColouredJacobian a(small.ode.jacobianPattern()), b(large.ode.jacobianPattern());
  const int looseColumns = [](const JacobianPattern& p) { return p.read - p.local; }(a.pattern());
  EXPECT_EQ(a.colourCount() - looseColumns, b.colourCount() - (b.pattern().read - b.pattern().local));
  // nonzeros per cell state independent of the series count, up to the loose part
  const double perStateA = static_cast<double>(a.pattern().nonzeros()) / a.pattern().local;
  const double perStateB = static_cast<double>(b.pattern().nonzeros()) / b.pattern().local;
  EXPECT_NEAR(perStateA, perStateB, 0.1 * perStateB);
}

TEST(SparseJacobian, ColouringKeepsColumnsThatShareARowApart) {
  // 4 local columns: 0 and 1 share row 0, 2 and 3 share row 3; 1 and 2 share nothing.
  PatternBuilder b(6);
  b.add(0, 1);
  b.add(3, 2);
  b.add(4, 4);
  b.add(1, 4);  // loose column 4 reaches local row 1
  const JacobianPattern p = b.build(4, 5);
  EXPECT_EQ(p.nonzeros(), 6 + 3);
  const auto groups = colourColumns(p);
  ASSERT_EQ(groups.size(), 3u);  // {0, 2}, {1, 3}, {4}; column 5 is never read
  EXPECT_EQ(groups[0], (std::vector<int>{0, 2}));
  EXPECT_EQ(groups[1], (std::vector<int>{1, 3}));
  EXPECT_EQ(groups[2], (std::vector<int>{4}));
  PatternBuilder bad(3);
  bad.add(2, 0);  // a loose row listing a local column
  EXPECT_THROW(colourColumns(bad.build(2, 3)), std::invalid_argument);
}

}  // namespace
}  // namespace packsim
