// Reference system A as its team built it: the 30 A fuse blows on any sustained
// current above 30 A (their report), and holds at or below it; the monitor IC
// supervises its link to the MCU, so a dead MCU opens the relay within the IC's
// 100 ms communication timeout instead of minutes later on the IC's own
// over-temperature comparator. Off the track the rules require balancing and
// over-voltage protection while charging: the charge bleeds the high cells (the SOC
// they lose is the charge their resistors carried) and ends at the full-cell voltage;
// a charger whose voltage loop drifts high is stopped by the cell over-voltage rule.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/overrides.hpp"
#include "core/sim/simulation.hpp"
#include "models/hw/fuse.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

TEST(ReferenceSystemA, TheFuseBlowsOnSustainedCurrentAboveThirtyAmpsOnly) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/eco_marathon_12s.yaml");
  const FuseConfig& f = s.hardware.fuse;
  ASSERT_TRUE(f.present);
  EXPECT_TRUE(std::isinf(fuseBlowTime_s(f, 30.0)));
  const double t31 = fuseBlowTime_s(f, 31.0);
  ASSERT_TRUE(std::isfinite(t31));
  EXPECT_NEAR(t31, f.i2t_A2s / (31.0 * 31.0 - 30.0 * 30.0), 1e-9);
  // Integrated at the BMS tick, the same current blows it at that time (within a tick).
  FuseState st;
  double t = 0.0;
  while (!st.blown && t < 120.0) {
    fuseStep(f, st, 31.0, 0.01);
    t += 0.01;
  }
  EXPECT_TRUE(st.blown);
  EXPECT_NEAR(t, t31, 0.011);
  // 30 A for an hour: never.
  FuseState held;
  for (int k = 0; k < 360000; ++k) fuseStep(f, held, 30.0, 0.01);
  EXPECT_FALSE(held.blown);
}

double firstEvent(const RunResult& r, const std::string& kind, const std::string& detail) {
  for (const Event& e : r.events)
    if (e.kind == kind && e.detail == detail) return e.time_s;
  return -1.0;
}

// The MCU hangs at 300 s. The IC last heard a frame within the 10 ms tick before, so its
// 100 ms timer expires 0.09-0.10 s after 300 s; the hardware sees the FAULT line at the
// next tick and the relay (released by the line in series with its coil) opens then.
TEST(ReferenceSystemA, TheMonitorIcNoticesADeadMcuWithinItsCommunicationTimeout) {
  const RunResult r = runScenario(loadScenarioFile(test::scenarioDir() + "/faults/a_host_dead.yaml"));
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/eco_marathon_12s.yaml");
  ASSERT_DOUBLE_EQ(s.hardware.afe.secondary.comm_timeout_s, 0.1);
  const double tick = s.bms.tick_s;
  const double line = firstEvent(r, "monitor_fault_line", "asserted");
  const double opened = firstEvent(r, "relay_contact", "opened");
  EXPECT_GE(line, 300.0 + 0.1 - tick - 1e-9);
  EXPECT_LE(line, 300.0 + 0.1 + tick + 1e-9);
  EXPECT_GE(opened, line);
  EXPECT_LE(opened, line + s.hardware.relay.open_delay_s + tick + 1e-9);
}

// The same fault with the supervision off: only the 65 C comparator opens it, minutes later.
TEST(ReferenceSystemA, WithoutLinkSupervisionOnlyTheOverTemperatureComparatorActs) {
  const RunResult r = runScenario(loadScenarioFile(test::scenarioDir() + "/faults/a_host_dead_unsupervised.yaml"));
  EXPECT_GT(firstEvent(r, "relay_contact", "opened"), 320.0 + 200.0);
}

// All four pack thermistors sit on the monitor IC's AUX inputs (the 16-cell part has eight),
// so its over-temperature comparator watches the fourth one (by cell 11) too: a cell
// overheating there after the MCU died still opens the relay. With the 3rd and 4th
// thermistor on the MCU's ADC, as the preset had them before, nothing would: the dead MCU
// reads them no more, and the relay stays closed (until the cells run flat).
TEST(ReferenceSystemA, AllFourThermistorsReachTheMonitorIcsOwnComparator) {
  const std::string file = test::scenarioDir() + "/faults/a_host_dead_unsupervised.yaml";
  const Scenario s = loadScenarioFile(file);
  EXPECT_EQ(s.hardware.afe.thermistors_per_device, 5);  // the four pack thermistors and the balancing board's
  const Overrides byCell11 = {{"faults.1.cell", "11"}};
  const double onIc = firstEvent(runScenario(loadScenarioFileWithOverrides(file, byCell11)), "relay_contact", "opened");
  EXPECT_GT(onIc, 320.0);
  EXPECT_LT(onIc, 700.0);
  Overrides onMcu = byCell11;
  onMcu.push_back({"hardware.afe.thermistors_per_device", "2"});
  EXPECT_LT(firstEvent(runScenario(loadScenarioFileWithOverrides(file, onMcu)), "relay_contact", "opened"), 0.0);
}

// A race with the MCU alive: it reads the IC every 10 ms, the timer never expires.
TEST(ReferenceSystemA, AnMcuThatTalksNeverTripsTheTimeout) {
  const RunResult r = runScenario(
      loadScenarioFileWithOverrides(test::scenarioDir() + "/eco_marathon_12s.yaml", {{"load.laps", "2"}}));
  EXPECT_LT(firstEvent(r, "monitor_fault_line", "asserted"), 0.0);
  EXPECT_FALSE(r.summary.tripped);
}

TEST(ReferenceSystemA, TheTimeoutTakesThePartsStepsOnly) {
  const std::string base = test::scenarioDir() + "/eco_marathon_12s.yaml";
  auto errorOf = [&](const Overrides& o) {
    try {
      loadScenarioFileWithOverrides(base, o);
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string("<no error>");
  };
  const std::string odd = errorOf({{"hardware.afe.secondary.comm_timeout_ms", "150"}});
  EXPECT_NE(odd.find("hardware.afe.secondary.comm_timeout_ms"), std::string::npos) << odd;
  EXPECT_NE(odd.find("100, 2000, 10000"), std::string::npos) << odd;
  const std::string pl536 =
      errorOf({{"hardware.afe.model", "bq76pl536a"}, {"hardware.afe.thermistors_per_device", "2"}});
  EXPECT_NE(pl536.find("only a bq76pl455a supervises its link"), std::string::npos) << pl536;
}

// Equal capacities (spread off) so each cell's SOC change is the charger's charge less
// its own bleed: the SOC a cell lost against the lowest cell (which never bleeds) times
// the capacity is the charge its resistor carried, from the recorded bleed current.
TEST(ReferenceSystemA, OffTrackChargeBleedsTheHighCellsAndEndsAtTheFullCellVoltage) {
  const Scenario s = loadScenarioFileWithOverrides(test::scenarioDir() + "/balance/eco_marathon_12s_charging.yaml",
                                                   {{"pack.spread.capacity_rel_sd", "0"}, {"output.interval_s", "1"}});
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  const size_t n = 12, last = rec.samples() - 1;
  const double R = s.hardware.balancing.resistor_ohm + s.hardware.balancing.rds_on_ohm;
  ASSERT_FALSE(r.summary.tripped) << r.summary.trip_reason;
  std::vector<double> bleed_As(n, 0.0);
  double maxCell_V = 0.0, maxBoard_C = 0.0;
  for (size_t i = 1; i <= last; ++i) {
    const double dt = rec.time_s[i] - rec.time_s[i - 1];
    for (size_t c = 0; c < n; ++c) {
      const double I = rec.balance_current_A[i * n + c], V = rec.cell_voltage_V[i * n + c];
      bleed_As[c] += I * dt;
      // The host opens the switches while the BQ76PL455A converts (bms.balancing.
      // measure_paused): 19 channels (12 cells, module, die, AUX0-4) at 100 us each, 1.9 ms
      // of every 10 ms read-out, so the mean current is 81 % of V/R.
      if (rec.hw_balancing[i * n + c])
        EXPECT_NEAR(I, 0.81 * V / R, 2e-3 * V / R) << "t " << rec.time_s[i] << " cell " << c + 1;
      else EXPECT_EQ(I, 0.0);
      maxCell_V = std::max(maxCell_V, V);
    }
    maxBoard_C = std::max(maxBoard_C, rec.board_temp_C[i]);
  }
  // Against the cell that bled least (the lowest never bleeds); measured: cell 4 bled
  // 812.2 As and lost 810.8 As.
  test::expectBleedIsTheSocLost(rec, bleed_As, 5.0 * 3600.0, 0.5);
  EXPECT_GT(bleed_As[3], 0.2 * 3600.0 * 0.9) << "cell 4 started 0.25 Ah high and bled most of it";
  // The imbalance the pack came in with (0.05 of SOC) is mostly gone.
  const double spread0 = 0.05;
  double lo = 1.0, hi = 0.0;
  for (size_t c = 0; c < n; ++c) lo = std::min(lo, rec.cell_soc[last * n + c]), hi = std::max(hi, rec.cell_soc[last * n + c]);
  EXPECT_LT(hi - lo, spread0 / 4);
  // The charge ends when the first cell reads the full-cell voltage, below over-voltage.
  size_t end = 1;
  while (end <= last && !(rec.charger_enable[end - 1] && !rec.charger_enable[end])) ++end;
  ASSERT_LE(end, last) << "the BMS ended the charge";
  const uint16_t* mv = &rec.meas_cell_voltage_mV[(end - 1) * n];
  EXPECT_GE(*std::max_element(mv, mv + n), 4180 - 5);
  for (size_t i = end + 1; i <= last; ++i) EXPECT_EQ(rec.charger_current_A[i], 0.0);
  EXPECT_LT(maxCell_V, 4.20);
  EXPECT_LT(maxBoard_C, s.bms.image.balance.boardMax_dC * 0.1 + 2.0) << "the board pause holds the resistors' heat";
}

// The charger's voltage loop 2 V high and no full-cell stop in the firmware: the cells
// pass 4.2 V and the 4.25 V / 500 ms over-voltage rule opens the relay, the charge stops,
// and no cell reaches the monitor IC's own 4.30 V comparator.
TEST(ReferenceSystemA, OverVoltageProtectionStopsARunawayCharger) {
  const RunResult r = runScenario(loadScenarioFile(test::scenarioDir() + "/faults/a_charger_overvoltage.yaml"));
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_EQ(r.summary.trip_reason, "cell_overvoltage");
  const double opened = firstEvent(r, "relay_contact", "opened");
  ASSERT_GT(opened, 0.0);
  const Recording& rec = r.rec;
  const size_t n = 12;
  double atTrip = 0.0, after = 0.0;
  for (size_t i = 0; i < rec.samples(); ++i) {
    const double* v = &rec.cell_voltage_V[i * n];
    const double top = *std::max_element(v, v + n);
    if (rec.time_s[i] <= r.summary.trip_time_s) atTrip = std::max(atTrip, top);
    else after = std::max(after, top);
    if (rec.time_s[i] > opened + 1.0) EXPECT_EQ(rec.charger_current_A[i], 0.0) << rec.time_s[i];
  }
  EXPECT_GT(atTrip, 4.25 - 0.01);  // measured 4.25 V (ADC noise, 1 s samples)
  EXPECT_LT(std::max(atTrip, after), 4.30);
}

}  // namespace
}  // namespace packsim
