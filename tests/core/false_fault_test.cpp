// FalseFaultWatch (core/sim/false_fault.hpp): a protection raised while no cell's truth
// came near its limit is a false_fault event; a trip on a real limit never is.
// First on a scripted truth, tick by tick; then on whole runs, where a channel gain fault
// and a drifting current sensor trip the BMS on readings alone, and a real over-voltage
// at the end of a charge and a real under-voltage at the end of a discharge trip it on
// the cells.
#include <gtest/gtest.h>

#include <bms/bms_faults.hpp>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "core/check/check.hpp"
#include "core/sim/false_fault.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::vector<std::string> eventsOf(const RunResult& r, const std::string& kind) {
  std::vector<std::string> out;
  for (const Event& e : r.events)
    if (e.kind == kind) out.push_back(e.detail);
  return out;
}

// Three cells, over-voltage at 4.2 V after 500 ms, a 100 ms tick and read-out: the BMS
// judges a reading up to 0.5 + 2 x 0.1 + 0.1 = 0.8 s old. The noiseless 100 uV converter
// gives the 10 mV floor as the honest error.
TEST(FalseFault, ARiseWithTheTruthFarFromTheLimitIsFalseAndNearItIsNot) {
  const Scenario s = test::scenarioFromYaml(
      test::simpleCellYaml(3) + "bms: {tick_ms: 100, readout: {period_ms: 100}, protections: {cell_overvoltage: "
                                "{threshold_V: 4.2, delay_ms: 500}}}\nload: {current_A: 1}\nrun: {duration_s: 20}\n");
  const uint32_t ov = 1u << static_cast<int>(bms::FaultId::CellOverVoltage);
  struct Case {
    const char* what;
    double nearUntil_s;  // the highest cell at 4.195 V (within 10 mV) up to this time, then 4.0 V
    bool falseFault;
  } cases[] = {{"never near", -1.0, true},
               {"near up to 0.9 s before the rise: outside the 0.8 s", 2.1, true},
               {"near up to 0.7 s before the rise: inside", 2.3, false},
               {"near at the rise", 100.0, false}};
  for (const Case& c : cases) {
    FalseFaultWatch w(s, 1);
    std::vector<std::pair<double, std::string>> events;
    const FalseFaultWatch::EventSink sink = [&](double t, const std::string& d) { events.emplace_back(t, d); };
    for (int k = 0; k <= 40; ++k) {
      const double t = k * 0.1;
      const std::vector<double> v = {3.9, t <= c.nearUntil_s + 1e-9 ? 4.195 : 4.0, 3.95};
      const std::vector<double> temp = {25.0, 25.0, 25.0};
      LimitWatch::CellExtremes cells;
      cells.volts.take(v);
      cells.temps.take(temp);
      w.tick(t, cells, 1.0, v, temp, k >= 30 ? ov : 0u, sink);
    }
    SCOPED_TRACE(c.what);
    ASSERT_EQ(events.size(), c.falseFault ? 1u : 0u);
    if (!c.falseFault) continue;
    EXPECT_DOUBLE_EQ(events[0].first, 3.0);
    EXPECT_EQ(events[0].second,
              "cell_overvoltage at 3.00 s: no cell's true voltage came within 10.0 mV of the 4.200 V limit in the 0.80 s "
              "before (the highest at the fault 4.000 V, cell 2): the BMS acted on a reading, not on the cells");
  }
}

// Every watched quantity, each near its limit and then far from it at the rise: the
// hottest cell against over-temperature (thermistors on cells only), the charge current
// against over-current in charge, the lowest cell against under-voltage.
TEST(FalseFault, EachQuantityIsJudgedOnItsOwnTruth) {
  const Scenario s = test::scenarioFromYaml(
      test::simpleCellYaml(2) + "bms: {tick_ms: 100, readout: {period_ms: 100}, protections: {overtemperature: "
                                "{threshold_C: 60, delay_ms: 0}, overcurrent_charge: {threshold_A: 10, delay_ms: 0}, "
                                "cell_undervoltage: {threshold_V: 3.0, delay_ms: 0}}}\nload: {current_A: 1}\n"
                                "run: {duration_s: 20}\n");
  using F = bms::FaultId;
  struct Case {
    F fault;
    double hot_C, pack_A, low_V;  // the truth at every tick
    bool falseFault;
  } cases[] = {{F::OverTemperature, 59.0, 0.0, 3.5, false}, {F::OverTemperature, 50.0, 0.0, 3.5, true},
               {F::OverCurrentCharge, 25.0, -9.95, 3.5, false}, {F::OverCurrentCharge, 25.0, -5.0, 3.5, true},
               {F::CellUnderVoltage, 25.0, 0.0, 3.005, false}, {F::CellUnderVoltage, 25.0, 0.0, 3.2, true}};
  for (const Case& c : cases) {
    FalseFaultWatch w(s, 1);
    int events = 0;
    const FalseFaultWatch::EventSink sink = [&](double, const std::string&) { ++events; };
    const std::vector<double> v = {c.low_V, 3.6}, temp = {25.0, c.hot_C};
    LimitWatch::CellExtremes cells;
    cells.volts.take(v);
    cells.temps.take(temp);
    for (int k = 0; k <= 20; ++k)
      w.tick(k * 0.1, cells, c.pack_A, v, temp, k >= 10 ? 1u << static_cast<int>(c.fault) : 0u, sink);
    EXPECT_EQ(events, c.falseFault ? 1 : 0) << bms::faultName(c.fault) << " " << c.hot_C << " " << c.pack_A << " " << c.low_V;
  }
}

std::string runYaml(const std::string& body, const std::string& soc = "0.8") {
  std::string cells = test::simpleCellYaml(3);
  cells.replace(cells.find("initial_soc: 0.8"), 16, "initial_soc: " + soc);
  return cells + "bms: {tick_ms: 100, protections: {cell_overvoltage: {threshold_V: 4.2, delay_ms: 500}, "
                                   "cell_undervoltage: {threshold_V: 3.5, delay_ms: 500}, overcurrent_discharge: "
                                   "{threshold_A: 20, delay_ms: 200}}}\n" + body;
}

// Group 2 reads 5 % high from 10 s: 4.03 V reads 4.23 V, past 4.2 V; no cell is above
// 4.04 V. The summary's `false fault` line and `check` say so.
TEST(FalseFault, AChannelGainTripIsAFalseFaultInTheEventsSummaryAndCheck) {
  const Scenario s = test::scenarioFromYaml(runYaml(
      "load: {current_A: 1}\nrun: {duration_s: 30}\nfaults: [{kind: channel_gain, group: 2, gain_error: 0.05, at_s: 10}]\n"));
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_EQ(r.summary.trip_reason, "cell_overvoltage");
  const std::vector<std::string> f = eventsOf(r, "false_fault");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].rfind("cell_overvoltage at 10.", 0), 0u) << f[0];
  EXPECT_NE(f[0].find("no cell's true voltage came within 10.0 mV of the 4.200 V limit"), std::string::npos) << f[0];
  const std::string text = formatSummary(s, r);
  EXPECT_NE(text.find("false fault     " + f[0]), std::string::npos) << text;
  const CheckOutcome c = judge(s, r);
  EXPECT_NE(std::find(c.warnings.begin(), c.warnings.end(), "a false fault: " + f[0]), c.warnings.end());
}

// A current-sense offset of 25 A reads a 1 A load as 26 A, past the 20 A limit.
TEST(FalseFault, ADriftedCurrentSensorTripIsAFalseFault) {
  const RunResult r = runScenario(test::scenarioFromYaml(runYaml(
      "load: {current_A: 1}\nrun: {duration_s: 10}\nfaults: [{kind: current_sensor_drift, offset_A: 25, at_s: 5}]\n")));
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_EQ(r.summary.trip_reason, "overcurrent_discharge");
  const std::vector<std::string> f = eventsOf(r, "false_fault");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_NE(f[0].find("the true pack current never came within 0.2 A of the 20 A limit"), std::string::npos) << f[0];
  EXPECT_NE(f[0].find("(it was 1.00 A at the fault)"), std::string::npos) << f[0];
}

// Real limits: a 1C charge into over-voltage, a 1C discharge into under-voltage, 20 A more
// than the 1 A load for 1 s (an over-current of the pack itself).
TEST(FalseFault, TripsOnRealLimitsAreNotFalse) {
  const char* bodies[] = {
      "load: {current_A: -2}\nrun: {duration_s: 900}\n", "load: {current_A: 2}\nrun: {duration_s: 900}\n",
      "load: {current_A: 1}\nrun: {duration_s: 10}\nfaults: [{kind: overcurrent, current_A: 20, at_s: 5, duration_s: 1}]\n"};
  const char* reasons[] = {"cell_overvoltage", "cell_undervoltage", "overcurrent_discharge"};
  for (int i = 0; i < 3; ++i) {
    const RunResult r = runScenario(test::scenarioFromYaml(runYaml(bodies[i], i == 1 ? "0.3" : "0.8")));
    SCOPED_TRACE(reasons[i]);
    ASSERT_TRUE(r.summary.tripped);
    EXPECT_EQ(r.summary.trip_reason, reasons[i]);
    EXPECT_TRUE(eventsOf(r, "false_fault").empty()) << testing::PrintToString(eventsOf(r, "false_fault"));
  }
}

}  // namespace
}  // namespace packsim
