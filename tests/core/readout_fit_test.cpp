// packsim's core firmware reads the whole monitor chain once per read-out period, by
// default every tick. Found by the generative campaign (issue 28): a 96s pack on six
// BQ76PL455A devices (250 kbaud UART) at the default 10 ms tick -- an ordinary
// Formula-Student-size pack -- failed at 0.025 s with "contract break in task 0 ... over
// its 10.000 ms budget", and so did a 240s pack on the BQ76PL536A. Now a probe measures
// one read-out before t = 0: an unstated period becomes the shortest multiple of the
// tick that holds it (a config_warning says so), a stated one too short is refused with
// its key, line and the shortest period that fits (core/sim/readout_fit.hpp).
#include <gtest/gtest.h>

#include <string>

#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::string pack455(const std::string& extra) {
  return "name: fs_96s\n"
         "pack: {series: 96, parallel: 2, initial_soc: 0.9, cell: {preset: lipo_5Ah, max_discharge_C: 10, "
         "max_charge_C: 2}}\n"
         "load: {current_A: 20}\n"
         "run: {duration_s: 1}\n" +
         extra;
}

bool hasEvent(const RunResult& r, const std::string& kind, const std::string& detailPart) {
  for (const auto& e : r.events)
    if (e.kind == kind && e.detail.find(detailPart) != std::string::npos) return true;
  return false;
}

TEST(ReadoutFit, AnUnstatedPeriodGrowsToHoldTheChainAndSaysSo) {
  const Scenario s = test::scenarioFromYaml(pack455("hardware: {afe: {model: bq76pl455a}}\n"));
  const RunResult r = runScenario(s);
  EXPECT_FALSE(hasEvent(r, "firmware_fault", "")) << "the core firmware broke its budget";
  EXPECT_TRUE(hasEvent(r, "config_warning", "bms.readout.period_ms = 20 (default (the shortest multiple of the 10 ms tick"));
  // the BMS did read the chain: every cell's measured voltage is a real reading at the end
  const Recording& rec = r.rec;
  ASSERT_EQ(rec.groups, 96);
  const size_t last = rec.samples() - 1;
  for (int g = 0; g < rec.groups; ++g)  // each group's cells: parallel 2, cell index g*2
    EXPECT_NEAR(rec.meas_cell_voltage_mV[last * 96 + static_cast<size_t>(g)],
                1e3 * rec.cell_voltage_V[last * static_cast<size_t>(rec.cells) + static_cast<size_t>(2 * g)], 50.0)
        << "group " << g + 1;
}

TEST(ReadoutFit, AStatedPeriodTooShortIsRefusedWithTheShortestThatFits) {
  const Scenario tooShort =
      test::scenarioFromYaml(pack455("hardware: {afe: {model: bq76pl455a}}\nbms: {readout: {period_ms: 10}}\n"));
  const std::string e = test::scenarioErrorOf([&] { runScenario(tooShort); });
  EXPECT_NE(e.find("bms.readout.period_ms = 10 is too short"), std::string::npos) << e;
  EXPECT_NE(e.find("the shortest period that holds it is 20 ms"), std::string::npos) << e;
  EXPECT_NE(e.find(":6"), std::string::npos) << "names the line of the key: " << e;
  // ... and the period it names is one that runs: no budget break, no warning
  const RunResult r = runScenario(
      test::scenarioFromYaml(pack455("hardware: {afe: {model: bq76pl455a}}\nbms: {readout: {period_ms: 20}}\n")));
  EXPECT_FALSE(hasEvent(r, "firmware_fault", ""));
  EXPECT_FALSE(hasEvent(r, "config_warning", "bms.readout.period_ms"));
}

TEST(ReadoutFit, AFasterBusKeepsTheReadoutAtTheTick) {
  // the read-out is mostly bus transfers: at 1 Mbaud (4x the default) it fits in a tick
  const RunResult r = runScenario(test::scenarioFromYaml(pack455("hardware: {afe: {model: bq76pl455a, baud: 1000000}}\n")));
  EXPECT_FALSE(hasEvent(r, "firmware_fault", ""));
  EXPECT_FALSE(hasEvent(r, "config_warning", "bms.readout.period_ms"));
}

}  // namespace
}  // namespace packsim
