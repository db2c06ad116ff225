// The simulated time-to-balance experiment (core/balance/balance_time) on a pack small
// and short enough for the quick set: the `BalanceTime` tests check it on system D's
// 110-cell boards over many hours (the `physics` label); this one runs the same code
// path, at rest, on reference system C's six cells for a few simulated hours, so the sanitizer
// pass (which runs the quick set) reaches it.
#include <gtest/gtest.h>

#include <cmath>

#include "core/balance/balance_table.hpp"
#include "core/balance/balance_time.hpp"
#include "core/scenario/load_scenario.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// System C (6s1p NCR18650, 47 ohm, no FET resistance), cell 1 0.2 Ah above the others at
// 3.9 V (about 65 mV: over the firmware's 50 mV start threshold), noise-free readings,
// balancing at rest (the scenario balances only while charging: the experiment's stated
// `when` replaces that). Independent expectations: the high cell bleeds I = V/47 ohm,
// 83 mA at 3.9 V, so the 0.2 Ah it holds above the others takes about 0.2 / 0.083 = 2.4 h;
// the truth is reached once the rest voltages are within the target (1.5 x the 10 mV stop
// threshold), before all of it is gone (the last 15 mV of OCV are about 0.05 Ah).
// Only the high cell needed to bleed: without noise no other cell's reading is ever
// 50 mV above the lowest, so nothing is wasted.
TEST(TimeToBalanceSmallPack, OneHighCellOfSystemCBleedsItsChargeAtVOverR) {
  Scenario s = loadScenarioFile(test::scenarioDir() + "/balance/bench_6s_balancing.yaml");
  s.hardware.cell_adc.noise_rms = 0.0;
  BalanceTimeOptions o;
  o.delta_Ah = 0.2;
  o.cell_V = 3.9;
  o.when = "always";
  o.max_hours = 5.0;
  const BalanceTimeResult r = balanceTime(s, o);
  ASSERT_EQ(r.rows.size(), 1u);
  const BalanceTimeRow& w = r.rows[0];
  ASSERT_TRUE(w.simulated);
  EXPECT_EQ(w.end_reason, "both_known") << w.firmware_note;
  EXPECT_NEAR(w.current_A, 3.9 / 47.0, 1e-9);
  EXPECT_NEAR(w.needed_Ah, 0.2, 1e-9);
  const double hand_h = 0.2 / (3.9 / 47.0);
  EXPECT_GT(w.true_h, 0.7 * hand_h);
  EXPECT_LT(w.true_h, hand_h) << "the target is reached before the last of the 0.2 Ah";
  EXPECT_NEAR(w.true_h, w.droop_to_target_h, 0.03 * w.droop_to_target_h);
  EXPECT_FALSE(std::isnan(w.firmware_h)) << w.firmware_note;
  EXPECT_GE(w.firmware_h, w.true_h - 0.05);
  EXPECT_LT(w.pack_wasted_Ah, 1e-6);
  EXPECT_NEAR(w.pack_useful_Ah + w.pack_wasted_Ah, w.bled_Ah, 1e-12);
  EXPECT_LT(w.bled_Ah, w.needed_Ah);
  EXPECT_GT(w.bled_Ah, 0.7 * w.needed_Ah);
  EXPECT_LT(w.final_spread_Ah, w.needed_Ah - 0.7 * w.needed_Ah + 1e-9);
  // Heat: I^2 R over the bleed, within the range V from the end to the start voltage gives.
  EXPECT_GT(w.pack_heat_Wh, w.bled_Ah * 3.7);
  EXPECT_LT(w.pack_heat_Wh, w.bled_Ah * 3.9 + 1e-9);
  EXPECT_FALSE(w.tripped);
  EXPECT_FALSE(w.within_rating) << "4.2 V across 47 ohm is 0.375 W > the scenario's 0.25 W resistors";
}

// With cells in parallel the table's "cell" is a series group: the header says so, and
// the group's delta takes its resistor twice as long as one cell's (the same V/R bleeds
// twice the charge).
TEST(TimeToBalanceSmallPack, AParallelPackCountsSeriesGroupsNotCells) {
  Scenario s = loadScenarioFile(test::scenarioDir() + "/balance/bench_6s_balancing.yaml");
  BalanceTimeOptions o;
  o.cell_V = 3.9;
  o.simulate = false;
  o.delta_Ah = 0.2;
  const BalanceTimeResult one = balanceTime(s, o);
  EXPECT_NE(balanceTimeTable(one).find("1 high cell, "), std::string::npos) << balanceTimeTable(one);
  s.pack.parallel = 2;
  o.delta_Ah = 0.4;  // 0.2 Ah in each of the group's two cells
  const BalanceTimeResult two = balanceTime(s, o);
  const std::string table = balanceTimeTable(two);
  EXPECT_NE(table.find("1 high series group (2 cells in parallel each), "), std::string::npos) << table;
  EXPECT_NE(table.find("a cell here is a series group, one resistor bleeding all 2"), std::string::npos) << table;
  ASSERT_EQ(two.rows.size(), 1u);
  EXPECT_NEAR(two.rows[0].const_I_all_h, 2.0 * one.rows[0].const_I_all_h, 1e-9);
}

}  // namespace
}  // namespace packsim
