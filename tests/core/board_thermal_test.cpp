// One thermal node per monitor board (hardware.balancing.cells_per_board), each IC's die
// on its own board, and the balancing noise floor (core/balance/noise_floor).
#include <gtest/gtest.h>

#include <cmath>

#include "core/balance/balance_analytic.hpp"
#include "core/balance/noise_floor.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario systemD() { return loadScenarioFile(test::scenarioDir() + "/balance/motorcycle_110s_balancing.yaml"); }

// docs/reference-systems.md D: all 36 resistors of a board on at 3.6 V put 36·3.6²/47 = 9.92 W into that
// board; the fourth board (cells 109-110) takes its own two.
TEST(BoardNodes, EachBoardTakesTheHeatOfTheCellsItMonitors) {
  Scenario s = systemD();
  s.pack.cell_overrides.clear();
  s.pack.spread = CellSpread{};
  s.pack.initial_soc = socAtOcv(s.pack.cell, 3.6);
  const Plant plant(s);
  ASSERT_EQ(plant.boardCount(), 4);
  std::vector<double> x(static_cast<size_t>(plant.stateSize()), 0.0);
  plant.initialState(x.data());
  PlantInputs in;
  in.balancing.assign(110, 1);
  PlantSignals sig = plant.makeSignals();
  plant.evaluate(0.0, x.data(), in, sig);
  const auto heat = [&](int b) { return sig.heat_W[static_cast<size_t>(plant.boardNodeOf(b))]; };
  EXPECT_NEAR(heat(0), 36 * 3.6 * 3.6 / 47.0, 0.005);
  EXPECT_NEAR(heat(0), 9.92, 0.01);
  EXPECT_NEAR(heat(1), heat(0), 1e-9);
  EXPECT_NEAR(heat(3), 2 * 3.6 * 3.6 / 47.0, 0.001);
  EXPECT_NEAR(heat(0) + heat(1) + heat(2) + heat(3), sig.balance_heat_W, 1e-9);
}

// A cell heating internally (25 W) reaches its thermistor: `overtemperature` trips, and
// keeps rising past the monitor ICs' board limit plus their die rise. The dies sit on
// their boards, which that cell does not heat: `board_overtemperature` never fires.
// (Before the board nodes, a die read its hottest cell + 5 C and fired too.)
TEST(BoardNodes, HotCellTripsOvertemperatureNeverBoardOvertemperature) {
  Scenario s = test::scenarioFromYaml(
      "name: hot\nseed: 1\n"
      "pack:\n  series: 6\n  initial_soc: 0.5\n  initial_temp_C: 25\n"
      "  cell: {capacity_Ah: 3, ocv_V: 3.7, r0_ohm: 0.02, heat_capacity_J_per_K: 40, g_ambient_W_per_K: 0.05}\n"
      "thermal:\n  nodes: [{name: board, heat_capacity_J_per_K: 30, g_ambient_W_per_K: 0.05}]\n"
      "ambient: {temp_C: 25}\n"
      "hardware:\n"
      "  afe: {model: bq76pl536a, cells_per_device: 6, thermistors_per_device: 2, secondary: {ot_C: 90}}\n"
      "  cell_adc: {noise_mV_rms: 0}\n"
      "  thermistors: {at_groups: [3]}\n"
      "  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}\n"
      "  balancing: {resistor_ohm: 47, board_node: board, board_thermistors: 1}\n"
      "bms:\n  tick_ms: 100\n  protections:\n"
      "    overtemperature: {threshold_C: 60, delay_ms: 1000}\n"
      "    board_overtemperature: {threshold_C: 70, delay_ms: 1000}\n"
      "load: {current_A: 0}\n"
      "faults:\n  - {kind: hot_cell, cell: 3, heat_W: 25, at_s: 1}\n"
      "run: {duration_s: 200, stop_after_trip_s: 150}\n"
      "output: {interval_s: 1}\n");
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_EQ(r.summary.trip_reason, "overtemperature");
  double hottest = 0.0;
  for (double t : r.rec.cell_temp_C) hottest = std::max(hottest, t);
  ASSERT_GT(hottest, 70.0 + 5.0) << "the cell passes the die limit minus its rise: the old die model would fire";
  EXPECT_LT(test::eventTime(r, "fault_active", "board_overtemperature"), 0.0);
}

// d2(n), the mean range of n standard normals: 2/√π for n = 2, 3/√π for n = 3 (closed
// forms), and the tabulated d2(10) = 3.078.
TEST(NoiseFloor, ExpectedRangeOfNormalsMatchesClosedForms) {
  EXPECT_NEAR(expectedRangeOfNormals(2), 2.0 / std::sqrt(M_PI), 1e-6);
  EXPECT_NEAR(expectedRangeOfNormals(3), 3.0 / std::sqrt(M_PI), 1e-6);
  EXPECT_NEAR(expectedRangeOfNormals(10), 3.078, 1e-3);
}

// System D's 110 channels at 1 mV rms (+ the LSB): single readings spread by more than
// the 5 mV stop threshold; 16 averaged readings do not.
TEST(NoiseFloor, WarnsWhenTheStopThresholdIsBelowTheNoiseSpreadOfNChannels) {
  Scenario s = systemD();
  EXPECT_EQ(balanceNoiseWarning(s), "") << "16 averaged readings: sigma/4";
  s.bms.image.balance.averageReadings = 1;
  const BalanceNoiseFloor f = balanceNoiseFloor(s);
  EXPECT_GT(f.expected_spread_V, 0.005);
  EXPECT_EQ(f.readings_needed, 2);
  const std::string w = balanceNoiseWarning(s);
  EXPECT_NE(w.find("d2(110)"), std::string::npos) << w;
  EXPECT_NE(w.find("average_readings >= 2"), std::string::npos) << w;
  s.run.duration_s = 1.0;
  EXPECT_EQ(test::eventTime(runScenario(s), "config_warning", "bms.balancing.stop_delta_mV"), 0.0);
}

// Hardware averaging exists only where the monitor class has it: the bq76pl455a's
// oversampling divides its cell noise by √n; asking a bq76pl536a for it is an error that
// names the field and the firmware alternative.
TEST(NoiseFloor, OversamplingOnlyOnTheMonitorThatAveragesInHardware) {
  const std::string head =
      "name: os\npack:\n  series: 4\n  cell: {capacity_Ah: 3, ocv_V: 3.7, r0_ohm: 0.02}\n"
      "hardware:\n  cell_adc: {noise_mV_rms: 2}\n  afe: {model: ";
  const Scenario s = test::scenarioFromYaml(head + "bq76pl455a, oversampling: 16}\nload: {current_A: 0}\nrun: {duration_s: 1}\n");
  EXPECT_NEAR(s.hardware.afe.cell_adc.noise_rms, 0.002 / 4.0, 1e-12);
  try {
    test::scenarioFromYaml(head + "bq76pl536a, oversampling: 16}\nload: {current_A: 0}\nrun: {duration_s: 1}\n");
    FAIL() << "oversampling on a bq76pl536a";
  } catch (const std::exception& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("oversampling"), std::string::npos) << m;
    EXPECT_NE(m.find("average_readings"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace packsim
