// Curves over discharged Ah use the preset's nominal capacity (models/cell/curve.hpp):
// a weaker cell reaches the curve's knee at its own SOC 0. Before, a 20 % weaker
// module read the nominal curve at (1 - soc)·its own Q, showed ~3.4 V at its SOC 0
// and ended the race no earlier than healthy ones (reference system B's situation).
// And a cell driven past empty or full is an event and a summary line, never silent.
#include <gtest/gtest.h>

#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// 3s2p of the system C preset (OCV table and Rint polynomial over discharged Ah),
// discharged at 0.2C per cell until the BMS trips at 2.5 V; module 2 optionally weak.
std::string race(double weakCapacity_Ah) {
  std::string y =
      "name: weak_module\nseed: 1\npack:\n  series: 3\n  parallel: 2\n  initial_soc: 1.0\n"
      "  cell: {preset: ncr18650_3p1Ah}\n";
  if (weakCapacity_Ah > 0.0) {
    const std::string q = std::to_string(weakCapacity_Ah);
    y += "  cells:\n    - {cell: 3, capacity_Ah: " + q + "}\n    - {cell: 4, capacity_Ah: " + q + "}\n";
  }
  return y +
         "hardware:\n  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n  thermistors: {at_groups: [1]}\n"
         "  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}\n"
         "bms:\n  tick_ms: 100\n  protections:\n    cell_undervoltage: {threshold_V: 2.5, delay_ms: 500}\n"
         "load: {current_A: 1.18}\nrun: {duration_s: 30000}\noutput: {interval_s: 10}\n";
}

TEST(CapacityAxis, WeakModuleEndsTheRaceInProportionToItsCapacity) {
  const RunResult healthy = runScenario(test::scenarioFromYaml(race(0.0)));
  const RunResult weak = runScenario(test::scenarioFromYaml(race(0.8 * 3.1)));
  ASSERT_TRUE(healthy.summary.tripped);
  ASSERT_TRUE(weak.summary.tripped);
  EXPECT_EQ(weak.summary.trip_reason, "cell_undervoltage");
  const double tc = test::eventTime(healthy, "relay", "close");
  // The weak module (cells 3, 4: series position 2) is the one that ends the race...
  EXPECT_TRUE(weak.summary.limit_cell == 3 || weak.summary.limit_cell == 4) << weak.summary.limit_cell;
  // ...after 80 % of the healthy pack's time: every cell reaches the knee at its own SOC 0
  // (the same curve read at its own SOC; heating at 0.2C moves it by far less than 1 %).
  const double ratio = (weak.summary.trip_time_s - tc) / (healthy.summary.trip_time_s - tc);
  EXPECT_NEAR(ratio, 0.8, 0.005) << weak.summary.trip_time_s << " vs " << healthy.summary.trip_time_s;
  // Neither race drives a cell past empty.
  for (const RunResult* r : {&healthy, &weak})
    for (const Event& e : r->events) EXPECT_NE(e.kind, "soc_out_of_range") << e.detail;
}

// A cell with no knee (linear OCV) and a BMS that does not stop it: the SOC runs
// below 0 — and the results say so.
TEST(CapacityAxis, CellDrivenPastEmptyOrFullIsAnEvent) {
  for (const double i_A : {3.0, -1.0}) {
    std::string y = test::simpleCellYaml() + "load: {current_A: " + std::to_string(i_A) +
                    "}\nrun: {duration_s: 900}\nbms:\n  protections:\n    cell_overvoltage: {threshold_V: 4.6}\n";
    y.replace(y.find("initial_soc: 0.8"), 16, i_A > 0 ? "initial_soc: 0.05" : "initial_soc: 0.95");
    const Scenario s = test::scenarioFromYaml(y);
    const RunResult r = runScenario(s);
    ASSERT_FALSE(r.summary.tripped);
    const double tc = test::eventTime(r, "relay", "close");
    const std::string dir = i_A > 0 ? "cell 1 below SOC 0" : "cell 1 above SOC 1";
    const double t = test::eventTime(r, "soc_out_of_range", dir);
    // 0.05 of 2 Ah at |I|: 120 s at 3 A, 360 s at 1 A after the relay closed (one tick late at most).
    const double expect = tc + 0.05 * 7200.0 / std::fabs(i_A);
    EXPECT_GE(t, expect - 1e-6) << dir;
    EXPECT_LE(t, expect + s.bms.tick_s + 1e-6) << dir;
    const std::string summary = formatSummary(s, r);
    EXPECT_NE(summary.find("SOC range       " + dir), std::string::npos) << summary;
  }
}

}  // namespace
}  // namespace packsim
