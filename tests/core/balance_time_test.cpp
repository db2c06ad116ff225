// Time to balance (core/balance/balance_time) against DOMAIN.md systems C and D, and the
// passive balancing branch's charge and heat accounting against a closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "core/balance/balance_time.hpp"
#include "core/sim/plant.hpp"
#include "models/afe/monitor_stack.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario preset(const std::string& rel) { return loadScenarioFile(test::scenarioDir() + "/" + rel); }

// DOMAIN.md C: 47 ohm at 3.6 V is 76.6 mA and 0.276 W; 0.561 Ah takes 7.32 h analytic.
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
  EXPECT_NEAR(r.rows[0].analytic_h, 7.32, 0.01);
}

// The simulation drains the high cell from 3.6 V down by 0.561 Ah; its OCV falls along
// the cell's curve, so the current falls from V0/R to V1/R. The time must lie between
// the constant-current times at the start and at the end voltage (plus 2 % for the
// decision latency, the I·R0 drop of the balancing cell and the cells the noisy
// readings let balance briefly), and the rest voltages end within the target.
TEST(BalanceTime, SystemCSimulationLiesBetweenStartAndEndVoltageEstimates) {
  const Scenario s = preset("balance/bench_6s_balancing.yaml");
  BalanceTimeOptions o;
  o.resistors_ohm = {47.0};
  o.delta_Ah = 0.561;
  o.cell_V = 3.6;
  const BalanceTimeResult r = balanceTime(s, o);
  const BalanceTimeRow& w = r.rows[0];
  ASSERT_TRUE(w.simulated);
  EXPECT_EQ(w.end_reason, "within_target");
  const CellParams& cell = s.pack.cell;
  const double socStart = socAtOcv(cell, 3.6);
  const double targetSoc = socStart - (0.561 - 0.005 / 0.31) / cell.capacity_Ah;  // within 5 mV (0.31 V/Ah)
  const double vEnd = ecm::ocv(cell, targetSoc);
  const double removed = (socStart - targetSoc) * cell.capacity_Ah;
  const double fastest_h = removed / (3.6 / 47.0);
  const double slowest_h = removed / (vEnd / 47.0);
  EXPECT_GT(w.simulated_h, fastest_h);
  EXPECT_LT(w.simulated_h, 1.02 * slowest_h);
  EXPECT_GT(w.simulated_h, w.analytic_h) << "the current falls as the cell drains";
  EXPECT_LT(w.simulated_h, 1.06 * w.analytic_h);
  EXPECT_GT(w.peak_board_C, 25.0);
  EXPECT_GT(w.energy_Wh, removed * vEnd);
}

// DOMAIN.md D: 1 Ah at 70 mA is about 14 h; 36 resistors on at 3.6 V dissipate 9.92 W.
TEST(BalanceTime, SystemDMaintenanceBalancingAndBoardPower) {
  BalanceTimeOptions o;
  o.delta_Ah = 1.0;
  o.cell_V = 3.3;
  o.high_cells = 36;
  o.simulate = false;
  const Scenario s = preset("balance/motorcycle_110s_balancing.yaml");
  const BalanceTimeResult r = balanceTime(s, o);
  EXPECT_NEAR(r.rows[0].current_A, 0.070, 0.0005);
  EXPECT_NEAR(r.rows[0].analytic_h, 14.0, 0.35);
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
      "  thermistors: {at_cells: [1]}\n"
      "  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0}\n"
      "  balancing: {resistor_ohm: 9.5, rds_on_ohm: 0.5, board_node: board}\n"
      "bms: {tick_ms: 1000, balance_time_s: 60, balancing: {when: always, min_cell_V: 2.0}}\n"
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

// The monitor IC (BQ76PL536A-like) stops balancing when its timer runs out unless the
// host re-arms it; a dead host (outputs frozen, no re-arm) cannot keep a cell draining.
TEST(MonitorBalanceTimer, StopsWhenTheTimerRunsOutUnlessReArmed) {
  MonitorConfig cfg;
  cfg.devices = 1;
  cfg.cells_per_device = 2;
  MonitorStack stack(cfg, 2, 1);
  const MonitorTruth truth = stack.makeTruth();
  bms::Outputs out{};
  out.balanceMask[0] = 0b10;
  out.balanceTime_s = 10;
  stack.hostWrite(0.0, out, truth);
  EXPECT_TRUE(stack.balancing(1, 9.5));
  EXPECT_FALSE(stack.balancing(0, 9.5));
  stack.hostWrite(9.0, out, truth);  // same mask, no re-arm: the timer is not rewritten
  EXPECT_FALSE(stack.balancing(1, 10.0));
  ++out.balanceArmCount;             // the host re-arms
  stack.hostWrite(12.0, out, truth);
  EXPECT_TRUE(stack.balancing(1, 21.5));
  EXPECT_FALSE(stack.balancing(1, 22.0));
}

}  // namespace
}  // namespace packsim
