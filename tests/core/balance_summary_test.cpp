// The summary's `balancing` line and balance_* figures (core/sim/balance_report.hpp)
// against the run's truth: at rest, with no load and no self-discharge, the charge the
// series groups lost is the charge the resistors bled; the spreads are the recorded
// cells' SOC times capacity; the start is the firmware's `balancing` event. And a pack of
// monitor boards reports the pack balancing while a member board bleeds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/scenario/load_scenario.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

constexpr int kSeries = 4;
constexpr double kCapacity_Ah = 2.0;

// 4s at rest, group 3 0.1 Ah high, 33 ohm resistors balancing after 5 s of rest.
Scenario restingPack(double duration_s) {
  return test::scenarioFromYaml(
      "name: rest_balance\nseed: 3\n"
      "pack:\n  series: 4\n  initial_soc: 0.8\n  initial_temp_C: 25\n"
      "  cell: {capacity_Ah: 2.0, ocv_V: {poly: [0.8, 3.4]}, r0_ohm: 0.02, rc_pairs: [{r_ohm: 0.01, c_F: 1000}],\n"
      "         heat_capacity_J_per_K: 40, g_ambient_W_per_K: 0.1}\n"
      "  cells: [{cell: 3, initial_soc: 0.85}]\n"
      "thermal: {nodes: [{name: board, heat_capacity_J_per_K: 30, g_ambient_W_per_K: 0.05}]}\n"
      "hardware:\n  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n  thermistors: {at_groups: [1]}\n"
      "  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}\n"
      "  balancing: {resistor_ohm: 33, rds_on_ohm: 0, board_node: board}\n"
      "ambient: {temp_C: 25}\n"
      "load: {current_A: 0}\nrun: {duration_s: " + std::to_string(duration_s) + "}\n"
      "bms:\n  tick_ms: 100\n  balance_time_s: 10\n"
      "  balancing: {when: rest, rest_s: 5, start_delta_mV: 20, stop_delta_mV: 5, min_cell_V: 3.0}\n");
}

// Highest minus lowest group charge (Ah) at recorded sample i (one cell per group).
double recordedSpread_Ah(const Recording& rec, size_t i) {
  double lo = INFINITY, hi = -INFINITY;
  for (int g = 0; g < kSeries; ++g) {
    const double q = rec.cell_soc[i * kSeries + static_cast<size_t>(g)] * kCapacity_Ah;
    lo = std::min(lo, q);
    hi = std::max(hi, q);
  }
  return hi - lo;
}

// Every group's charge summed (Ah) at recorded sample i.
double recordedCharge_Ah(const Recording& rec, size_t i) {
  double q = 0.0;
  for (int g = 0; g < kSeries; ++g) q += rec.cell_soc[i * kSeries + static_cast<size_t>(g)] * kCapacity_Ah;
  return q;
}

TEST(BalanceSummary, BledChargeIsWhatTheGroupsLostAndTheSpreadsAreTheTruths) {
  const Scenario s = restingPack(1800.0);
  const RunResult r = runScenario(s);
  const BalanceSummary& b = r.summary.balance;
  const Recording& rec = r.rec;
  ASSERT_TRUE(b.present);
  const size_t last = rec.time_s.size() - 1;
  ASSERT_DOUBLE_EQ(rec.time_s[last], r.summary.duration_s);
  // At rest every coulomb the groups lost went through a resistor (the monitor's bias
  // current is not modelled on this plain ADC): conservation to rounding.
  ASSERT_GT(b.bled_Ah, 0.01);
  EXPECT_NEAR(b.bled_Ah, recordedCharge_Ah(rec, 0) - recordedCharge_Ah(rec, last), 1e-9);
  EXPECT_NEAR(b.spread_start_Ah, 0.1, 1e-12);
  EXPECT_NEAR(b.spread_start_Ah, recordedSpread_Ah(rec, 0), 1e-12);
  EXPECT_NEAR(b.spread_end_Ah, recordedSpread_Ah(rec, last), 1e-12);
  EXPECT_LT(b.spread_end_Ah, b.spread_start_Ah);
  // Alike cells: the imbalance is the charge spread, and the line gives it alone.
  EXPECT_NEAR(b.imbalance_start_Ah, b.spread_start_Ah, 1e-9);
  EXPECT_NEAR(b.imbalance_end_Ah, b.spread_end_Ah, 1e-9);
  EXPECT_GT(b.heat_Wh, 0.0);
  // The start and the end are the firmware's events.
  EXPECT_DOUBLE_EQ(b.started_s, test::eventTime(r, "balancing", "balancing"));
  const std::string text = formatSummary(s, r);
  char start[64];
  std::snprintf(start, sizeof start, "balancing       from %.2f s, ", b.started_s);
  EXPECT_TRUE(has(text, start)) << text;
  char bled[64];
  std::snprintf(bled, sizeof bled, "; bled %.3f Ah, ", b.bled_Ah);
  EXPECT_TRUE(has(text, bled)) << text;
  if (b.balanced_s >= 0.0) {
    EXPECT_DOUBLE_EQ(b.balanced_s, test::eventTime(r, "balancing", "balanced"));
  } else {
    EXPECT_TRUE(has(text, "not balanced by the end")) << text;
  }
}

// Group 1 a 2.6 Ah cell at the others' SOC: it holds 0.48 Ah more than they do at the same
// rest voltage, which is no imbalance. The imbalance is group 3's 0.05 x 2 Ah = 0.1 Ah
// above the lowest rest voltage (its OCV curve is the others', so that is SOC 0.8);
// the charge spread, 0.8 x 2.6 - 0.8 x 2 = 0.48 Ah, gets its own line, which says why.
// At the end, each group's excess from the recorded SOC: (SOC - the lowest SOC) x capacity.
TEST(BalanceSummary, ABiggerCellAtTheSameRestVoltageIsNoImbalance) {
  Scenario s = restingPack(1800.0);
  CellOverride big;
  big.cell = 0;
  big.capacity_Ah = 2.6;
  s.pack.cell_overrides.push_back(big);
  const RunResult r = runScenario(s);
  const BalanceSummary& b = r.summary.balance;
  const Recording& rec = r.rec;
  EXPECT_NEAR(b.imbalance_start_Ah, 0.1, 1e-9);
  EXPECT_NEAR(b.spread_start_Ah, 0.48, 1e-9);
  const size_t last = rec.time_s.size() - 1;
  const auto socAt = [&](int g) { return rec.cell_soc[last * kSeries + static_cast<size_t>(g)]; };
  double lowest = 1.0, excess = 0.0;
  for (int g = 0; g < kSeries; ++g) lowest = std::min(lowest, socAt(g));
  for (int g = 0; g < kSeries; ++g) excess = std::max(excess, (socAt(g) - lowest) * (g == 0 ? 2.6 : kCapacity_Ah));
  EXPECT_NEAR(b.imbalance_end_Ah, excess, 1e-9);
  EXPECT_LT(b.imbalance_end_Ah, 0.05);
  const std::string text = formatSummary(s, r);
  char line[200];
  std::snprintf(line, sizeof line, "series groups' imbalance 0.100 Ah at the start, %.3f Ah at the end (truth: ",
                b.imbalance_end_Ah);
  EXPECT_TRUE(has(text, line)) << text;
  std::snprintf(line, sizeof line, "charge spread 0.480 Ah at the start, %.3f Ah at the end: it also counts the groups' "
                "capacities, which differ", b.spread_end_Ah);
  EXPECT_TRUE(has(text, line)) << text;
  EXPECT_FALSE(has(formatSummary(restingPack(10.0), runScenario(restingPack(10.0))), "charge spread"))
      << "alike cells: no charge-spread line";
}

// With cells in parallel a group rests at one voltage once its cells share their charge:
// its SOC is its charge over its capacity. 4s2p, one cell of group 3 at 0.85 and its
// neighbour at the others' 0.8: the group sits at 0.825, 0.025 x 4 Ah = 0.1 Ah above.
TEST(BalanceSummary, AParallelGroupsImbalanceIsItsChargeOverItsCapacity) {
  Scenario s = restingPack(10.0);
  s.pack.parallel = 2;
  s.pack.cell_overrides.clear();
  CellOverride high;
  high.cell = 4;  // cell 5: group 3's first
  high.initial_soc = 0.85;
  s.pack.cell_overrides.push_back(high);
  const RunResult r = runScenario(s);
  EXPECT_NEAR(r.summary.balance.imbalance_start_Ah, 0.1, 1e-9);
  EXPECT_NEAR(r.summary.balance.spread_start_Ah, 0.1, 1e-9);
}

// No balancing hardware: no line, no figures.
TEST(BalanceSummary, APackWithoutBalancingHasNoLine) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(2) + test::kSimpleLoadYaml);
  const RunResult r = runScenario(s);
  EXPECT_FALSE(r.summary.balance.present);
  EXPECT_FALSE(has(formatSummary(s, r), "\nbalancing")) << formatSummary(s, r);
}

// A user's firmware on a board with balancing resistors: packsim does not see its
// balancing decision, and the run's balancing channel (packsim's core's) keeps its first
// value. The line said "(its last status: disabled)", a status the firmware never gave,
// then "the firmware never reported balancing", which it has no way to: it says what
// packsim sees, the switches (none here: the example firmware does not balance).
TEST(BalanceSummary, AUserFirmwareIsNotGivenPacksimsCoresBalancingStatus) {
  const Scenario s = test::scenarioFromYaml(
      "extends: firmware/c_example_firmware.yaml\nrun: {duration_s: 2}\n"
      "hardware: {balancing: {resistor_ohm: 33}}\n");
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.balance.present);
  const std::string text = formatSummary(s, r);
  EXPECT_TRUE(has(text, "\nbalancing       the firmware set no balancing switch; bled 0.000 Ah")) << text;
  EXPECT_FALSE(has(text, "its last status")) << text;
}

// System D at rest: its second monitor board's 36 cells sit 1 Ah high and that board
// bleeds them, decided on its own MCU. The pack host's own cells are the low ones, so the
// host alone says "balanced"; the pack's status (recorded and in the events) is
// "balancing" whenever a switch is on. 700 s: the rest of 600 s, then a minute and more.
TEST(BalanceSummary, APackOfBoardsIsBalancingWhileAMemberBoardBleeds) {
  Scenario s = loadScenarioFile(test::scenarioDir() + "/balance/motorcycle_110s_balancing.yaml");
  s.run.duration_s = 700.0;
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  const size_t groups = static_cast<size_t>(rec.groups);
  size_t on = 0;
  for (size_t i = 0; i < rec.time_s.size(); ++i) {
    bool any = false;
    for (size_t g = 0; g < groups; ++g) any = any || rec.hw_balancing[i * groups + g] != 0;
    if (!any) continue;
    ++on;
    EXPECT_EQ(rec.balance_status[i], 4) << "at " << rec.time_s[i] << " s";  // balancing
  }
  EXPECT_GT(on, 5u);
  EXPECT_GT(test::eventTime(r, "balancing", "balancing"), 600.0);
  EXPECT_GT(r.summary.balance.bled_Ah, 0.0);
}

}  // namespace
}  // namespace packsim
