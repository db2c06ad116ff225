// Time to balance (core/balance/balance_time) against reference systems C and D, and the
// passive balancing branch's charge and heat accounting against a closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "core/balance/balance_time.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "core/balance/noise_floor.hpp"
#include "core/text_fmt.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario preset(const std::string& rel) { return loadScenarioFile(test::scenarioDir() + "/" + rel); }

// docs/reference-systems.md C: 47 ohm at 3.6 V is 76.6 mA and 0.276 W; 0.561 Ah takes 7.32 h analytic.
TEST(BalanceTime, SystemCAnalyticMatchesDomainFigures) {
  BalanceTimeOptions o;
  o.resistors_ohm = {47.0};
  o.delta_Ah = 0.561;
  o.cell_V = 3.6;
  o.simulate = false;
  const BalanceTimeResult r = balanceTime(preset("balance/bench_6s_balancing.yaml"), o);
  ASSERT_EQ(r.rows.size(), 1u);
  EXPECT_NEAR(r.rows[0].current_A, 0.07659, 0.0001);
  EXPECT_NEAR(r.rows[0].power_W, 0.276, 0.001);
  EXPECT_NEAR(r.rows[0].const_I_all_h, 7.32, 0.01);
}

// System D's first board: 36 cells 2 Ah above the rest at 3.9 V, 47 ohm, the fast
// integrator (the answer does not depend on the solver at a 1 s tick).
BalanceTimeOptions systemDBoard(double resistor_ohm) {
  BalanceTimeOptions o;
  o.resistors_ohm = {resistor_ohm};
  o.delta_Ah = 2.0;
  o.cell_V = 3.9;
  o.high_cells = 36;
  o.max_hours = 60.0;
  return o;
}

// System D's balancing scenario with the board cooling straight to the 30 C air (C = 400
// J/K, G = 0.57 W/K), as the closed forms below assume: the scenario's warm pack skin
// the boards sit on and the monitor ICs' thermistor bias (a few mA from some cells) are
// left out here.
Scenario systemD() {
  Scenario s = preset("balance/motorcycle_110s_balancing.yaml");
  s.run.solver = RunConfig::Solver::Fast;
  s.pack.initial_temp_C = 30.0;
  s.hardware.afe.thermistor_bias_A = 0.0;
  ThermalNodeConfig board;
  board.name = "balancing_board";
  board.heat_capacity_J_per_K = 400.0;
  board.g_ambient_W_per_K = 0.57;
  s.thermal.nodes = {board};
  return s;
}

// Noise-free readings: the true time against the closed form with OCV droop,
// (R + Rds_on)·∫dQ/OCV(Q) over the charge the high cells lose until their OCV is within
// the target of the low cells' (core/balance/balance_analytic), within 1 %. The firmware
// (as configured) stops each cell at 5 mV above the minimum reading, so without noise
// the truth settles at ~5 mV: the target that measures it is 6 mV. No low cell bleeds.
TEST(BalanceTime, SystemDNoiseFreeMatchesTheDroopClosedFormWithin1Percent) {
  Scenario s = systemD();
  s.hardware.afe.cell_adc.noise_rms = 0.0;
  s.hardware.cell_adc.noise_rms = 0.0;
  BalanceTimeOptions o = systemDBoard(47.0);
  o.target_mV = 6.0;
  const BalanceTimeRow w = balanceTime(s, o).rows[0];
  ASSERT_TRUE(w.simulated);
  EXPECT_EQ(w.end_reason, "both_known") << w.firmware_note;
  EXPECT_NEAR(w.true_h, w.droop_to_target_h, 0.01 * w.droop_to_target_h);
  EXPECT_GE(w.firmware_h, w.true_h - 0.05) << "declared balanced only once the readings are within 5 mV";
  EXPECT_LT(w.pack_wasted_Ah, 1e-4) << "only the tick-by-tick integration's rounding";
  EXPECT_NEAR(w.needed_Ah, 72.0, 1e-6);
  EXPECT_DOUBLE_EQ(w.paused_fraction, 0.0);
  EXPECT_LT(w.peak_board_C, 60.0);
}

// (System D's 0.3 A rms current sensor also draws the rest-noise warning on the SOC's
// 0.2 A rest threshold: not this test's matter.)
std::vector<std::string> butRestNoise(const std::vector<std::string>& warnings) {
  std::vector<std::string> out;
  for (const std::string& w : warnings)
    if (w.rfind("bms.soc.rest_current_A", 0) != 0) out.push_back(w);
  return out;
}

// The scenario's own 1 mV-rms noise and thresholds, decisions on the mean of 16 readings:
// within 2 % of the same closed form, and the cells that needed nothing bled less than
// 1 % of the high cells' charge. With single readings (the stop threshold below the
// noise spread of 110 channels) the load-time warning states the statistic and the
// minimum of 110 noisy readings makes balanced cells bleed many times more.
TEST(BalanceTime, SystemDWithNoiseStaysWithin2PercentAndWastesUnder1Percent) {
  const BalanceTimeResult averaged = balanceTime(systemD(), systemDBoard(47.0));
  const BalanceTimeRow& w = averaged.rows[0];
  ASSERT_TRUE(w.simulated);
  EXPECT_TRUE(butRestNoise(averaged.warnings).empty()) << testing::PrintToString(averaged.warnings);
  EXPECT_EQ(w.end_reason, "both_known") << w.firmware_note;
  EXPECT_NEAR(w.true_h, w.droop_to_target_h, 0.02 * w.droop_to_target_h);
  EXPECT_FALSE(std::isnan(w.firmware_h)) << w.firmware_note;
  EXPECT_LT(w.pack_wasted_Ah, 0.01 * w.needed_Ah);
  EXPECT_NEAR(w.pack_useful_Ah + w.pack_wasted_Ah, w.bled_Ah, 1e-12);

  Scenario s = systemD();
  s.bms.image.balance.averageReadings = 1;
  const BalanceTimeResult single = balanceTime(s, systemDBoard(47.0));
  const std::vector<std::string> spread = butRestNoise(single.warnings);
  ASSERT_EQ(spread.size(), 1u) << testing::PrintToString(single.warnings);
  EXPECT_NE(spread[0].find("d2(110)"), std::string::npos) << spread[0];
  EXPECT_GT(single.rows[0].pack_wasted_Ah, 10.0 * w.pack_wasted_Ah + 0.05);
}

// 22 ohm puts ~25 W into the first board: the pause (60 C, resume 50 C) binds. The
// board node (C = 400 J/K, G = 0.57 W/K to 30 C ambient, tau = C/G) heats towards
// T_inf = 30 + P/G while on and cools towards 30 C while paused:
//   first heating 30 -> 60 C:  t0  = tau·ln((T_inf - 30)/(T_inf - 60))
//   each cycle on  50 -> 60 C: ton = tau·ln((T_inf - 50)/(T_inf - 60))
//              off 60 -> 50 C: toff = tau·ln((60 - 30)/(50 - 30))
// The cells need the no-pause time t_b of balancing (the droop form); after t0 they
// balance a fraction ton/(ton + toff) of the time, so t = t0 + (t_b - t0)·(ton + toff)/ton.
TEST(BalanceTime, BoardPauseBindsLikeTheDutyCycleOfTheBoardTimeConstant) {
  Scenario s = systemD();
  const BalanceTimeRow w = balanceTime(s, systemDBoard(22.0)).rows[0];
  ASSERT_TRUE(w.simulated);
  ASSERT_FALSE(std::isnan(w.true_h)) << w.firmware_note;
  const double C = 400.0, G = 0.57, tau = C / G, amb = 30.0, on = 60.0, resume = 50.0;
  const CellParams& cell = s.pack.cell;
  const double socHigh = socAtOcv(cell, 3.9);
  const double vMean = 0.5 * (3.9 + ecm::ocv(cell, socHigh - 2.0 / cell.capacity_Ah));
  const double P = 36.0 * vMean * vMean / 22.0;
  const double Tinf = amb + P / G;
  const double t0 = tau * std::log((Tinf - amb) / (Tinf - on));
  const double ton = tau * std::log((Tinf - resume) / (Tinf - on));
  const double toff = tau * std::log((on - amb) / (resume - amb));
  const double tb = w.droop_to_target_h * 3600.0;
  const double expected_s = t0 + (tb - t0) * (ton + toff) / ton;
  EXPECT_NEAR(w.true_h * 3600.0, expected_s, 0.03 * expected_s);
  const double pausedExpected = (expected_s - tb) / expected_s;
  EXPECT_NEAR(w.paused_fraction, pausedExpected, 0.03);
  EXPECT_NEAR(w.peak_board_C, on, 1.5) << "held at the pause threshold";
  ASSERT_EQ(w.board_peak_C.size(), 4u);
  EXPECT_LT(w.board_peak_C[1], 31.0) << "the other boards' resistors stay off";
}

// A resistor list: the fastest value within limits is marked, and where the pause binds
// it is not the smallest resistor the V/R estimate would pick.
TEST(BalanceTime, SweepMarksTheFastestWithinLimitsWhereThePauseBinds) {
  BalanceTimeOptions o = systemDBoard(22.0);
  o.resistors_ohm = {22.0, 33.0};
  const BalanceTimeResult r = balanceTime(systemD(), o);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_LT(r.rows[0].const_I_all_h, r.rows[1].const_I_all_h);
  EXPECT_GT(r.rows[0].paused_fraction, 0.2);
  EXPECT_LT(r.rows[1].true_h, r.rows[0].true_h) << "33 ohm beats 22 ohm once the board pause binds";
  EXPECT_TRUE(r.rows[1].fastest);
  EXPECT_FALSE(r.rows[0].fastest);
}

// System C on its charger (balances only while charging, ends the charge when the first
// cell reads 4.18 V): the high cell bleeds I_bal while the charger pushes I_chg, so it
// reaches full later by about I_bal·t/(I_chg - I_bal), t the charge without balancing;
// I_bal at the cell's mean voltage over the charge. The balancing then goes on while the
// pack sits on the charger until the firmware declares balanced.
TEST(BalanceTime, DuringChargeAddsTheTimeTheBleedCurrentCosts) {
  const Scenario s = preset("balance/bench_6s_balancing.yaml");
  BalanceTimeOptions o;
  o.resistors_ohm = {47.0};
  o.during_charge = true;
  const BalanceTimeResult r = balanceTime(s, o);
  const BalanceTimeRow& w = r.rows[0];
  ASSERT_TRUE(w.simulated);
  EXPECT_TRUE(w.end_reason == "charge_done" || w.end_reason == "both_known") << w.end_reason;
  EXPECT_FALSE(std::isnan(w.true_h)) << w.firmware_note;
  ASSERT_GT(w.charge_without_h, 0.3);
  const double iBal = 0.5 * (r.cell_V + 4.18) / 47.0, iChg = s.charger.current_A;
  const double added_h = iBal * w.charge_without_h / (iChg - iBal);
  EXPECT_NEAR(w.charge_added_h, added_h, 0.1 * added_h);
  EXPECT_GT(w.firmware_h, w.charge_h) << "top balancing goes on after the charge, on the charger";
  EXPECT_FALSE(w.within_rating) << "4.2 V across 47 ohm is 0.375 W > the scenario's 0.25 W resistors";
}

// A BMS that ends the charge itself (bms.charge_full_cell_V) leaves the charger on
// standby, not done: the run went on to --max-hours and ended "time_limit" (bench_6s at
// 100 ohm: still balancing at 3 h) or, balancing declared, ran on idle. Now the row says
// when the BMS ended the charge, on what, and the imbalance left; and once the charger is
// off and the firmware has stopped balancing, the run ends: charge_ended_by_bms.
TEST(BalanceTime, DuringChargeABmsThatEndsTheChargeSaysSoAndWhatWasLeft) {
  const Scenario s = preset("balance/bench_6s_balancing.yaml");
  BalanceTimeOptions o;
  o.resistors_ohm = {100.0};
  o.during_charge = true;
  o.max_hours = 3.0;
  const BalanceTimeRow w = balanceTime(s, o).rows[0];
  EXPECT_EQ(w.end_reason, "time_limit");
  // The charger delivers until the BMS switches it off (charge_h, its last tick above the
  // end current): the note's time is that one, and the imbalance left the row's own.
  EXPECT_NE(w.firmware_note.find(fmt("the BMS ended the charge at %.2f h and kept it off: the highest cell, cell 3", w.charge_h)),
            std::string::npos) << w.firmware_note;
  EXPECT_NE(w.firmware_note.find("its bms.charge_full_cell_V 4.180 V"), std::string::npos) << w.firmware_note;
  EXPECT_NE(w.firmware_note.find(fmt("; %.3f Ah of imbalance left at 3.00 h (truth)", w.final_imbalance_Ah)), std::string::npos)
      << w.firmware_note;
  EXPECT_LT(w.charge_h, 1.0);

  // System A's firmware declares balanced at 3.65 h, an hour and a half after its charge
  // end at 1.18 h, and then stops: the run ends there, not at --max-hours.
  const Scenario a = preset("balance/eco_marathon_12s_charging.yaml");
  BalanceTimeOptions oa;
  oa.during_charge = true;
  oa.max_hours = 10.0;
  const BalanceTimeRow wa = balanceTime(a, oa).rows[0];
  EXPECT_FALSE(wa.tripped) << wa.firmware_note;
  EXPECT_EQ(wa.end_reason, "charge_ended_by_bms") << wa.firmware_note;
  EXPECT_FALSE(std::isnan(wa.firmware_h));
  EXPECT_GT(wa.firmware_h, wa.charge_h);
  EXPECT_NE(wa.firmware_note.find(fmt("the BMS ended the charge at %.2f h", wa.charge_h)), std::string::npos) << wa.firmware_note;
  EXPECT_NE(wa.firmware_note.find("Ah of imbalance left at 3.6"), std::string::npos) << wa.firmware_note;
}

// balance-time raises the BMS tick to 1 s; a BQ76PL455A whose link supervision times out
// after 100 ms (system A) latched its FAULT line at the first such tick, and every row of
// the bundled eco_marathon_12s_charging "tripped: monitor_fault at 0.00 h" -- a run of the
// scenario itself never trips. The tick now stays within half the timeout.
TEST(BalanceTime, TheRaisedTickKeepsWithinTheMonitorsCommTimeout) {
  const Scenario a = preset("balance/eco_marathon_12s_charging.yaml");
  ASSERT_DOUBLE_EQ(a.hardware.afe.secondary.comm_timeout_s, 0.1);
  BalanceTimeOptions o;
  o.max_hours = 0.05;
  o.when = "always";
  const BalanceTimeRow w = balanceTime(a, o).rows[0];
  EXPECT_FALSE(w.tripped) << w.firmware_note;
  EXPECT_NE(w.end_reason, "tripped") << w.firmware_note;
}

// docs/reference-systems.md D: 1 Ah at 70 mA is about 14 h; 36 resistors on at 3.6 V dissipate 9.92 W.
TEST(BalanceTime, SystemDMaintenanceBalancingAndBoardPower) {
  BalanceTimeOptions o;
  o.delta_Ah = 1.0;
  o.cell_V = 3.3;
  o.high_cells = 36;
  o.simulate = false;
  const Scenario s = preset("balance/motorcycle_110s_balancing.yaml");
  const BalanceTimeResult r = balanceTime(s, o);
  EXPECT_NEAR(r.rows[0].current_A, 0.070, 0.0005);
  EXPECT_NEAR(r.rows[0].const_I_all_h, 14.0, 0.35);
  o.cell_V = 3.6;
  const BalanceTimeResult hot = balanceTime(s, o);
  EXPECT_NEAR(hot.rows[0].board_power_W, 36 * 3.6 * 3.6 / 47.0, 1e-9);
  EXPECT_NEAR(hot.rows[0].board_power_W, 9.92, 0.01);
}

TEST(BalanceTime, BadOptionsNameTheOptionAndItsRange) {
  const Scenario s = preset("balance/bench_6s_balancing.yaml");
  BalanceTimeOptions o;
  o.resistors_ohm = {0.5};
  try {
    balanceTime(s, o);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--resistor"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("1 .. 10000"), std::string::npos);
  }
  o.resistors_ohm = {47};
  o.delta_Ah = 3.0;
  o.cell_V = 3.6;
  EXPECT_THROW(balanceTime(s, o), std::invalid_argument);  // 3 Ah below 3.6 V empties the cell
  // The same for the analytic rows alone: they printed "5.000 Ah to remove" from 3.1 Ah
  // cells at SOC 0.55, with to-target times of a low cell held at SOC 0.
  o.simulate = false;
  o.delta_Ah = 5.0;
  o.cell_V.reset();
  try {
    balanceTime(s, o);
    FAIL() << "5 Ah below a 3.1 Ah cell at SOC 0.55 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--delta-Ah: 5 Ah below a cell at"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("(SOC 0.55) empties it; at most 1.705 Ah"), std::string::npos) << e.what();
  }
  o.delta_Ah = 1.7;  // within the 0.55 × 3.1 Ah the high cell holds
  EXPECT_NO_THROW(balanceTime(s, o));
  // A cell at rest above its OCV at SOC 1 was taken, its bleed current at that voltage.
  o.delta_Ah = 0.5;
  o.cell_V = 4.6;
  const double top = ecm::ocv(s.pack.cell, 1.0);
  try {
    balanceTime(s, o);
    FAIL() << "a cell resting at 4.6 V accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fmt("--cell-V: 4.6 V is outside the cell's rest voltages, %.4g", ecm::ocv(s.pack.cell, 0.0)) +
                                         fmt(" .. %.4g V", top)),
              std::string::npos) << e.what();
  }
  o.cell_V = top;
  EXPECT_NO_THROW(balanceTime(s, o));
}

// Two cells, linear OCV a + b·soc, no RC pairs: the high cell's balancing current is
// I = k·(a + b·soc)/R_b with k = 1/(1 + R0/R_b), so it decays exponentially with
// τ = 3600·Q·R_b/(k·b). Charge and heat over [t_on, T] follow in closed form.
TEST(BalanceAccounting, ChargeAndHeatMatchTheClosedFormTo1e6) {
  const std::string yaml =
      "name: acct\nseed: 1\n"
      "pack:\n  series: 2\n  initial_soc: 0.2\n"
      "  cell: {capacity_Ah: 1.0, ocv_V: {poly: [1.0, 3.0]}, r0_ohm: 0.05, heat_capacity_J_per_K: 40, g_ambient_W_per_K: 0.1}\n"
      "  cells: [{cell: 1, initial_soc: 0.8}]\n"
      "thermal:\n  nodes: [{name: board, heat_capacity_J_per_K: 20, g_ambient_W_per_K: 0.2}]\n"
      "hardware:\n"
      "  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0}\n"
      "  thermistors: {at_groups: [1]}\n"
      "  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}\n"
      "  balancing: {resistor_ohm: 9.5, rds_on_ohm: 0.5, board_node: board}\n"
      "bms: {tick_ms: 1000, balance_time_s: 60, balancing: {when: always, min_cell_V: 2.0, measure_paused: false}}\n"
      "load: {current_A: 0}\n"
      "run: {duration_s: 3600, rtol: 1e-10}\n"
      "output: {interval_s: 1}\n";
  const Scenario s = test::scenarioFromYaml(yaml);
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  size_t on = 0;
  while (on < rec.samples() && rec.hw_balancing[on * 2] == 0) ++on;
  ASSERT_LT(on, rec.samples());
  for (size_t i = on; i < rec.samples(); ++i) ASSERT_EQ(rec.hw_balancing[i * 2], 1) << "the timer is re-armed";
  const double t_on = rec.time_s[on], T = rec.time_s.back();
  const double a = 3.0, b = 1.0, Rb = 10.0, R0 = 0.05, Q = 1.0;
  const double k = 1.0 / (1.0 + R0 / Rb);
  const double tau = 3600.0 * Q * Rb / (k * b);
  const double soc0 = 0.8, x0 = soc0 + a / b;  // soc + a/b decays with τ
  const double decay = std::exp(-(T - t_on) / tau);
  const double charge_As = 3600.0 * Q * x0 * (1.0 - decay);
  const double i0 = k * b * x0 / Rb;
  const double heat_J = i0 * i0 * Rb * tau / 2.0 * (1.0 - decay * decay);
  EXPECT_NEAR(r.quad[kQuadBalanceCharge_As], charge_As, 1e-6 * charge_As);
  EXPECT_NEAR(r.quad[kQuadBalanceHeat_J], heat_J, 1e-6 * heat_J);
  // Independent of the quadrature: the SOC the cell lost.
  const double socEnd = rec.cell_soc[(rec.samples() - 1) * 2];
  EXPECT_NEAR(3600.0 * Q * (soc0 - socEnd), r.quad[kQuadBalanceCharge_As], 1e-6 * charge_As);
  // Energy: Σ∫OCV·I = heat (cells' I²R0 + balancing branch, in the board node) at zero load.
  EXPECT_NEAR(r.quad[kQuadChemEnergy_J], r.quad[kQuadHeat_J], 1e-6 * r.quad[kQuadChemEnergy_J]);
}

}  // namespace
}  // namespace packsim
