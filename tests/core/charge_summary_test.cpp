// The summary's `charge` line, the `charger` events the BMS's charger enable raises and the
// /summary charge_* figures (core/sim/charge_summary.hpp) against the run's recording:
// a firmware that ends the charge on a cell's loaded voltage (bms.charge_full_cell_V)
// switches the charger off far from full, and the line says at what voltage, under what
// current and at what true SOC; a charge the charger ends at its taper says that; a
// firmware that never enables the charger says that.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// 3s1p NCR18650 at 30 % on a 3 A (about 1C) CC-CV charger, readings noise-free, every tick
// recorded; `bms` adds to the BMS block.
Scenario charging(const std::string& bms) {
  return test::scenarioFromYaml(
      "name: charge_end\nseed: 2\n"
      "pack: {series: 3, initial_soc: 0.3, cell: {preset: ncr18650_3p1Ah}}\n"
      "hardware:\n"
      "  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n"
      "  thermistors: {at_groups: [1]}\n"
      "  current_sense: {shunt_ohm: 0.001, amp_gain: 10, noise_A_rms: 0}\n"
      "bms: {tick_ms: 1000" + bms + "}\n"
      "load: {charger: {current_A: 3.0, voltage_V: 12.6, end_current_A: 0.3}}\n"
      "run: {duration_s: 6000}\n"
      "output: {interval_s: 1}\n");
}

// charge_full_cell_V 4.10 V at 3 A: the cells' ~0.1 V of I·R rise brings the first reading
// there well before the cells are full. The BMS switches the charger off on that tick; the
// figures are the recorded truth of that tick, and the charger delivers nothing after.
TEST(ChargeSummary, AChargeEndedOnALoadedCellVoltageSaysAtWhatVoltageCurrentAndSoc) {
  const Scenario s = charging(", charge_full_cell_V: 4.10");
  const RunResult r = runScenario(s);
  const ChargeSummary& c = r.summary.charge;
  const Recording& rec = r.rec;
  ASSERT_TRUE(c.present);
  EXPECT_DOUBLE_EQ(c.on_s, test::eventTime(r, "charger", "enabled by the BMS"));
  ASSERT_GT(c.off_s, c.on_s);
  EXPECT_DOUBLE_EQ(c.off_s, test::eventTime(r, "charger", "disabled by the BMS"));
  const size_t i = test::sampleAt(rec, c.off_s);
  const double* v = &rec.cell_voltage_V[i * 3];
  const double highest = *std::max_element(v, v + 3);
  EXPECT_EQ(c.off_cell, static_cast<int>(std::max_element(v, v + 3) - v) + 1);
  EXPECT_DOUBLE_EQ(c.off_cell_V, highest);
  // The firmware reads whole mV, rounded from the 0.1 mV code: 4100 mV from 4.09950 V (and
  // half an LSB) up. That tick reached it, the tick before did not.
  EXPECT_GE(highest, 4.0995 - 0.5e-4);
  const double* before = &rec.cell_voltage_V[(i - 1) * 3];
  EXPECT_LT(*std::max_element(before, before + 3), 4.0995 + 0.5e-4);
  EXPECT_DOUBLE_EQ(c.off_current_A, -rec.pack_current_A[i]);
  EXPECT_NEAR(c.off_current_A, 3.0, 1e-9) << "still in constant current";
  EXPECT_NEAR(c.off_soc_mean, (rec.cell_soc[i * 3] + rec.cell_soc[i * 3 + 1] + rec.cell_soc[i * 3 + 2]) / 3.0, 1e-12);
  EXPECT_LT(c.off_soc_mean, 0.95) << "a loaded-voltage end leaves the cells short of full";
  for (size_t k = i + 1; k < rec.samples(); ++k) ASSERT_EQ(rec.charger_current_A[k], 0.0) << rec.time_s[k];
  EXPECT_GT(rec.charger_current_A[i - 1], 0.0);

  const std::string text = formatSummary(s, r);
  char line[300];
  std::snprintf(line, sizeof line, "charge          enabled by the BMS at %.2f s, switched off at %.2f s (", c.on_s, c.off_s);
  EXPECT_TRUE(has(text, line)) << text;
  std::snprintf(line, sizeof line, "then the highest cell, cell %d, was at %.3f V under %.2f A of charge; mean SOC %.3f (truth)",
                c.off_cell, c.off_cell_V, c.off_current_A, c.off_soc_mean);
  EXPECT_TRUE(has(text, line)) << text;
}

// Without charge_full_cell_V the charger ends the charge at its taper current, the BMS's
// enable on to the end: the line names the charger's `done` event.
TEST(ChargeSummary, AChargeTheChargerEndsAtItsTaperSaysSo) {
  const Scenario s = charging("");
  const RunResult r = runScenario(s);
  const double done = test::eventTime(r, "charger", "done");
  ASSERT_GT(done, 0.0);
  EXPECT_LT(r.summary.charge.off_s, 0.0);
  char line[200];
  std::snprintf(line, sizeof line, "; the charger ended at its taper end current at %.2f s\n", done);
  EXPECT_TRUE(has(formatSummary(s, r), line)) << formatSummary(s, r);
}

// A 3 C cell on a BMS that refuses to charge below 5 C: the charger is never enabled.
TEST(ChargeSummary, AChargeTheBmsNeverAllowsSaysSo) {
  Scenario s = test::scenarioFromYaml(
      "name: cold\nseed: 2\n"
      "pack: {series: 1, initial_soc: 0.3, initial_temp_C: 3, cell: {preset: ncr18650_3p1Ah}}\n"
      "hardware:\n  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n  thermistors: {at_groups: [1]}\n"
      "  current_sense: {shunt_ohm: 0.001, amp_gain: 10, noise_A_rms: 0}\n"
      "ambient: {temp_C: 3}\n"
      "bms: {tick_ms: 1000, protections: {undertemperature_charge: {threshold_C: 5, delay_ms: 1000}}}\n"
      "load: {charger: {current_A: 3.0, voltage_V: 4.2, end_current_A: 0.3}}\n"
      "run: {duration_s: 60}\n");
  const RunResult r = runScenario(s);
  EXPECT_LT(r.summary.charge.on_s, 0.0);
  for (uint8_t e : r.rec.charger_enable) ASSERT_EQ(e, 0);
  EXPECT_TRUE(has(formatSummary(s, r), "charge          the BMS never enabled the charger\n")) << formatSummary(s, r);
}

// No charger: no line, no figures.
TEST(ChargeSummary, ARunWithoutAChargerHasNoLine) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(2) + test::kSimpleLoadYaml);
  const RunResult r = runScenario(s);
  EXPECT_FALSE(r.summary.charge.present);
  EXPECT_FALSE(has(formatSummary(s, r), "\ncharge ")) << formatSummary(s, r);
}

}  // namespace
}  // namespace packsim
