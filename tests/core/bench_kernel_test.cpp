// The floor kernel of the benchmarks (bench/floor_kernel) makes the same update as the
// fast integrator, so "ratio to the floor" compares like with like: on a series string
// (no current split) at a held current, both advance every cell's SOC, RC voltages and
// temperature identically to rounding -- with the cell's temperature dependence (system
// D's Arrhenius R0 and reversible heat, system E's R0 table over temperature).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "bench/floor_kernel.hpp"
#include "core/scenario/load_scenario.hpp"
#include "core/sim/fast_integrator.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

void expectSameTrajectory(const std::string& file, double current_A) {
  Scenario s = loadScenarioFile(test::scenarioDir() + "/" + file);
  s.thermal.nodes.clear();  // the floor is the cells alone (no pack skin, no board)
  ASSERT_TRUE(s.pack.cell.usesTemperature());
  ASSERT_EQ(s.pack.parallel, 1);
  s.load.quantity = LoadProfile::Quantity::Current_A;  // the scooter's ride is in watts; both run a held current
  const Plant plant(s);
  const double kCurrent_A = current_A;
  constexpr double kTick_s = 0.01;
  constexpr int kTicks = 200;

  HardwareFaults faults;
  PlantInputs in;
  in.faults = &faults;
  in.relay_closed = true;
  in.load = LoadSegment{0.0, INFINITY, kCurrent_A, 0.0};
  FastIntegrator integ(plant, in, FastSettings{});
  std::vector<double> x(static_cast<size_t>(plant.stateSize() + kQuadCount), 0.0);
  plant.initialState(x.data());
  integ.reset(0.0, x.data());

  bench::FloorPack floor(plant, s.thermal.cell_to_cell_W_per_K, s.ambient_C.at(0.0));
  floor.prepare(kTick_s);
  std::vector<double> v(static_cast<size_t>(floor.cells()));
  for (int k = 1; k <= kTicks; ++k) {
    integ.advance(k * kTick_s, k * kTick_s);
    floor.step(kCurrent_A, v.data());
  }
  ASSERT_EQ(integ.stats().steps, kTicks);  // one sub-step per tick, as in the benchmark
  const double* xs = integ.state();
  for (int c = 0; c < floor.cells(); ++c) {
    const double* xc = plant.cellStates(xs, c);
    EXPECT_NEAR(floor.soc(c), xc[CellLayout::soc], 1e-13) << "cell " << c;
    for (int k = 0; k < plant.pack().layout.n_rc; ++k)
      EXPECT_NEAR(floor.vrc(c, k), xc[plant.pack().layout.rc(k)], 1e-13) << "cell " << c << " rc " << k;
    EXPECT_NEAR(floor.temp_C(c), xs[plant.tempIndex(c)], 1e-11) << "cell " << c;
  }
}

TEST(BenchFloorKernel, SameCellTrajectoryAsFastIntegrator) {
  expectSameTrajectory("motorcycle_110s.yaml", 180.0);  // Arrhenius R0, reversible heat
  expectSameTrajectory("scooter_16s_lto.yaml", 36.0);   // R0 table over temperature
}

}  // namespace
}  // namespace packsim
