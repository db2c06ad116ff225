// A pack that starts past a cell-voltage limit is told so at load time
// (core/scenario/start_voltage_warning.hpp): the cell of test::simpleCellYaml has
// OCV = 0.8 soc + 3.4 V and R0 = 20 mOhm, so at SOC 0.8 it rests at 4.040 V and gives
// 4.020 V under the 1 A load.
#include <gtest/gtest.h>

#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario withCell(const std::string& cellExtra, const std::string& rest = "") {
  std::string y = test::simpleCellYaml();
  y.replace(y.find("    r0_ohm: 0.02\n"), 17, "    r0_ohm: 0.02\n" + cellExtra);
  return test::scenarioFromYaml(y + test::kSimpleLoadYaml + rest);
}

std::string startWarning(const Scenario& s) {
  std::string all;
  for (const std::string& w : s.warnings)
    if (w.rfind("the cells start", 0) == 0) all += w + "\n";
  return all;
}

TEST(StartVoltage, OpenCircuitBelowVMinIsWarned) {
  const std::string w = startWarning(withCell("    v_min_V: 4.1\n"));
  EXPECT_NE(w.find("the cells start at 4.040 V open-circuit at pack.initial_soc = 0.8 (test.yaml:5), pack.initial_temp_C = "
                   "25 (test.yaml:6), below pack.cell.v_min_V = 4.1 (test.yaml:"),
            std::string::npos) << w;
}

TEST(StartVoltage, UnderTheFirstLoadValueBelowVMinIsWarned) {
  const std::string w = startWarning(withCell("    v_min_V: 4.03\n"));
  EXPECT_NE(w.find("the cells start at 4.020 V under the load's first 1 A (1 A a cell through R0 20 mOhm, from 4.040 V "
                   "open-circuit"),
            std::string::npos) << w;
  EXPECT_EQ(startWarning(withCell("    v_min_V: 4.01\n")), "");  // above it: nothing
  EXPECT_EQ(startWarning(withCell("")), "");
}

TEST(StartVoltage, BelowTheBmsUnderVoltageLimitIsWarnedAndTheRunTripsAtTheStart) {
  // Was: no word at load time; the run tripped 0.5 s in ("TRIP at 0.51 s (cell_undervoltage)").
  const Scenario s = withCell("", "bms: {protections: {cell_undervoltage: {threshold_V: 4.1, delay_ms: 500}}}\n");
  const std::string w = startWarning(s);
  EXPECT_NE(w.find("below bms.protections.cell_undervoltage.threshold_V = 4.1 (test.yaml:"), std::string::npos) << w;
  EXPECT_NE(w.find("acts after its delay_ms (500 ms)"), std::string::npos) << w;
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_GE(r.summary.trip_time_s, 0.5);
  EXPECT_LE(r.summary.trip_time_s, 0.5 + s.bms.tick_s + 1e-9);
}

TEST(StartVoltage, ACellOverrideStartingHighIsNamed) {
  std::string y = test::simpleCellYaml(2);
  y.replace(y.find("    r0_ohm: 0.02\n"), 17, "    r0_ohm: 0.02\n    v_max_V: 4.15\n");
  y.replace(y.find("  cell:\n"), 8, "  cells: [{cell: 2, initial_soc: 1.0}]\n  cell:\n");
  const std::string w = startWarning(test::scenarioFromYaml(y + test::kSimpleLoadYaml));
  EXPECT_NE(w.find("the cells start at 4.200 V open-circuit at pack.cells[0].initial_soc = 1.0 (test.yaml:"), std::string::npos) << w;
  EXPECT_NE(w.find("above pack.cell.v_max_V = 4.15"), std::string::npos) << w;
}

}  // namespace
}  // namespace packsim
