// External inputs (core/sim/external_inputs.hpp) and a driver-run SimulationRun (an FMU's
// view of the loop): unset inputs change nothing, a run driven tick by tick equals
// runScenario, and set inputs act on the plant as the analytic solutions say.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/sim/bms_bridge.hpp"  // HardwareStatus
#include "core/sim/external_inputs.hpp"
#include "core/sim/simulation.hpp"
#include "models/cell/ecm.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

using test::kSimpleLoadYaml;
using test::scenarioFromYaml;
using test::simpleCellYaml;

TEST(ExternalInputs, UnsetInputsChangeNothing) {
  PlantInputs pin;
  pin.load = LoadSegment{0.0, 30.0, 2.0, 0.1};
  bms::Inputs in{};
  in.eSwitchInternal = true;
  in.chargerPresent = true;
  const ExternalInputs none;
  EXPECT_FALSE(none.applyToPlant(5.0, pin));
  EXPECT_EQ(pin.load.t1_s, 30.0);
  EXPECT_EQ(pin.load.slope_A_per_s, 0.1);
  EXPECT_FALSE(pin.ambient_C.has_value());
  none.applyToPins(in);
  EXPECT_TRUE(in.eSwitchInternal);
  EXPECT_TRUE(in.chargerPresent);
}

TEST(ExternalInputs, ALoadIsHeldFromTheTickItIsApplied) {
  PlantInputs pin;
  pin.load = LoadSegment{0.0, 30.0, 2.0, 0.1};
  ExternalInputs ext;
  ext.load_A_or_W = 3.0;
  ext.ambient_C = 40.0;
  EXPECT_TRUE(ext.applyToPlant(5.0, pin));
  EXPECT_EQ(pin.load.t0_s, 5.0);
  EXPECT_EQ(pin.load.t1_s, std::numeric_limits<double>::infinity());
  EXPECT_EQ(pin.load.current_A(100.0), 3.0);
  EXPECT_EQ(*pin.ambient_C, 40.0);
  EXPECT_FALSE(ext.applyToPlant(5.1, pin));  // held: no restart of the integrator
  bms::Inputs in{};
  ext.estop_external_pulled = true;
  ext.charger_present = false;
  in.chargerPresent = true;
  ext.applyToPins(in);
  EXPECT_TRUE(in.eSwitchExternal);
  EXPECT_FALSE(in.chargerPresent);
}

// A driver alternating advance() and tick() with no inputs set is runScenario.
TEST(SimulationRunDriver, TickAndAdvanceWithoutInputsEqualRunScenario) {
  const Scenario s = scenarioFromYaml(simpleCellYaml(3) + kSimpleLoadYaml);
  const RunResult ref = runScenario(s);
  SimulationRun run(s);
  bool going = run.tick();
  while (going) {
    run.advance();
    going = run.tick();
  }
  const RunResult r = run.finish();
  EXPECT_EQ(r.rec.time_s, ref.rec.time_s);
  EXPECT_EQ(r.rec.pack_voltage_V, ref.rec.pack_voltage_V);
  EXPECT_EQ(r.rec.cell_soc, ref.rec.cell_soc);
}

TEST(SimulationRunDriver, ADriverRunGoesPastTheScenarioEnd) {
  const Scenario s = scenarioFromYaml(simpleCellYaml(1) + kSimpleLoadYaml);  // 10 s
  SimulationRun run(s, RunEnd::Driver);
  ASSERT_TRUE(run.tick());
  while (run.time_s() < 15.0 - 1e-9) {
    run.advance();
    ASSERT_TRUE(run.tick());
  }
  EXPECT_FALSE(run.ended());
  EXPECT_NEAR(run.time_s(), 15.0, 1e-9);
  // Past the end of the scenario's (constant) load it still draws 1 A.
  EXPECT_NEAR(run.signals().pack_current_A, 1.0, 1e-12);
}

double cellSoc(const SimulationRun& run) { return run.plant().cellStates(run.state(), 0)[CellLayout::soc]; }

// Charge conservation: an external 4 A over 100 s with the relay closed takes
// 4·100 / 3600 / 2 Ah of SOC from the cell (the scenario's own load is 1 A).
TEST(SimulationRunDriver, AnExternalLoadDrainsTheCellAsCoulombCountingSays) {
  const Scenario s = scenarioFromYaml(simpleCellYaml(1) + kSimpleLoadYaml);
  SimulationRun run(s, RunEnd::Driver);
  ExternalInputs ext;
  ext.load_A_or_W = 4.0;
  run.setExternalInputs(ext);
  run.tick();
  auto runTo = [&](double t_s) {
    while (run.time_s() < t_s - 1e-9) {
      run.advance();
      run.tick();
    }
  };
  runTo(10.0);
  ASSERT_TRUE(run.hardware().relay_closed);
  EXPECT_NEAR(run.signals().pack_current_A, 4.0, 1e-12);
  const double soc10 = cellSoc(run);
  runTo(110.0);
  EXPECT_NEAR(soc10 - cellSoc(run), 4.0 * 100.0 / 3600.0 / 2.0, 1e-9);
}

// Newton cooling: with no current, a cell at 25 degC in a 45 degC ambient follows
// T(t) = 45 - 20·exp(-t·G/C), G = 0.1 W/K, C = 40 J/K.
TEST(SimulationRunDriver, AnExternalAmbientHeatsTheIdleCellAsNewtonSays) {
  const Scenario s = scenarioFromYaml(simpleCellYaml(1) + kSimpleLoadYaml);
  SimulationRun run(s, RunEnd::Driver);
  ExternalInputs ext;
  ext.load_A_or_W = 0.0;
  ext.ambient_C = 45.0;
  run.setExternalInputs(ext);
  run.tick();
  while (run.time_s() < 400.0 - 1e-9) {
    run.advance();
    run.tick();
  }
  EXPECT_EQ(run.signals().ambient_C, 45.0);
  const double T_C = run.state()[run.plant().tempIndex(0)];
  EXPECT_NEAR(T_C, 45.0 - 20.0 * std::exp(-400.0 * 0.1 / 40.0), 2e-3);
}

}  // namespace
}  // namespace packsim
