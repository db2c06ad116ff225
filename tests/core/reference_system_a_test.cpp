// Reference system A as its team built it: the 30 A fuse blows on any sustained
// current above 30 A (their report), and holds at or below it; the monitor IC
// supervises its link to the MCU, so a dead MCU opens the relay within the IC's
// 100 ms communication timeout instead of minutes later on the IC's own
// over-temperature comparator.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

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
  EXPECT_EQ(s.hardware.afe.thermistors_per_device, 4);
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

}  // namespace
}  // namespace packsim
