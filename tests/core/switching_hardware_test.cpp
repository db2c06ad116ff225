// Switching hardware in the loop: precharge into the bus capacitance against the
// analytic RC charge, a precharge that cannot finish (shorted load), the fuse's I²t,
// and the relay's operate/release delays and weld.
#include <gtest/gtest.h>

#include <cmath>

#include "core/scenario/load_scenario.hpp"
#include "core/sim/simulation.hpp"
#include "models/hw/fuse.hpp"
#include "models/hw/relay.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// 12 cells at a flat 3.5 V: a 42 V pack, precharged through 100 Ω into 1000 µF
// (RC = 0.1 s). The BMS finishes when the bus is within 5 % of the pack, which an RC
// charge reaches after RC·ln(20) = 3.0 RC.
std::string prechargeScenario(const std::string& leak) {
  return "name: pre\nseed: 3\n"
         "pack:\n  series: 12\n  initial_soc: 0.5\n  cell: {capacity_Ah: 5, ocv_V: 3.5, r0_ohm: 0.01}\n"
         "hardware:\n  cell_adc: {noise_mV_rms: 0}\n  current_sense: {noise_A_rms: 0}\n"
         "  bus_adc: {full_scale_V: 60, bits: 12}\n"
         "  precharge: {r_ohm: 100, bus_capacitance_uF: 1000" + leak + "}\n"
         "bms:\n  tick_ms: 10\n"
         "  precharge: {done_delta_V: 2.1, done_current_A: 0.05, timeout_ms: 500, pause_ms: 200, retries: 2}\n"
         "load: {segments: [{duration_s: 1.5, current_A: 0}, {duration_s: 1.5, current_A: 2}]}\n"
         "run: {stop_after_trip_s: 0.5}\noutput: {interval_s: 0.01}\n";
}

TEST(Precharge, FinishesNearThreeRc) {
  const RunResult r = runScenario(test::scenarioFromYaml(prechargeScenario("")));
  const double start = test::eventTime(r, "precharge", "charging (attempt 1)");
  const double closing = test::eventTime(r, "precharge", "closing (attempt 1)");
  ASSERT_GE(start, 0.0);
  ASSERT_GT(closing, start);
  const double analytic = 0.1 * std::log(20.0);  // 0.2996 s
  // The BMS sees the gap at its 10 ms ticks, one tick after the contact closed at the
  // earliest; the bus ADC's 15 mV steps move the crossing by < 1 ms.
  EXPECT_GE(closing - start, analytic - 0.011);
  EXPECT_LE(closing - start, analytic + 0.021);
  EXPECT_FALSE(r.summary.tripped);
  // The main relay then carries the load: 2 A flows in the second segment.
  EXPECT_NEAR(r.rec.pack_current_A[test::sampleAt(r.rec, 2.0)], 2.0, 1e-9);
}

TEST(Precharge, ShortedLoadTimesOutAfterItsRetries) {
  // 1 Ω across the bus: it settles at 42·1/101 = 0.42 V and never comes within 2.1 V.
  const RunResult r = runScenario(test::scenarioFromYaml(prechargeScenario(", bus_leak_ohm: 1")));
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_EQ(r.summary.trip_reason, "precharge_failed");
  const double start = test::eventTime(r, "precharge", "charging (attempt 1)");
  EXPECT_GE(test::eventTime(r, "precharge", "charging (attempt 3)"), 0.0);
  EXPECT_LT(test::eventTime(r, "precharge", "charging (attempt 4)"), 0.0);
  // Three attempts of 500 ms with two 200 ms pauses between them: 1.9 s (+ a tick each).
  const double failed = test::eventTime(r, "fault_active", "precharge_failed");
  EXPECT_GE(failed - start, 1.9 - 1e-9);
  EXPECT_LE(failed - start, 1.9 + 0.05);
  // The main relay never closed.
  EXPECT_LT(test::eventTime(r, "relay_contact", "closed"), 0.0);
}

TEST(Fuse, BlowTimeFollowsTheMeltingIntegral) {
  const FuseConfig c;  // 30 A, 2500 A²s, hold 110 %
  // Q = (I² − I_hold²)·t = I²t  ⇒  t = 2500 / (60² − 33²) = 0.9956 s at 60 A.
  const double t60 = 2500.0 / (3600.0 - 33.0 * 33.0);
  EXPECT_NEAR(fuseBlowTime_s(c, 60.0), t60, 1e-12);
  FuseState s;
  double t = 0.0;
  while (!s.blown && t < 10.0) {
    fuseStep(c, s, 60.0, 0.001);
    t += 0.001;
  }
  EXPECT_NEAR(t, t60, 0.0011);
  // 33 A (the hold current) never blows it; a 0.1 s pulse of 100 A (891 A²s) does not either.
  EXPECT_TRUE(std::isinf(fuseBlowTime_s(c, 33.0)));
  FuseState p;
  for (int k = 0; k < 100; ++k) fuseStep(c, p, 100.0, 0.001);
  EXPECT_FALSE(p.blown);
  EXPECT_NEAR(p.q_A2s, (1e4 - 1089.0) * 0.1, 1e-6);
}

TEST(Fuse, SustainedOvercurrentBlowsItInTheLoop) {
  // System A with the BMS's own current protections off: only the 30 A fuse is left.
  // (60 A is beyond the ±33 A range of its current sense, so with the BMS intact the
  // rail-stuck current-sensor fault opens the relay after 500 ms, before the fuse.)
  Scenario s = loadScenarioFile(std::string(PACKSIM_SCENARIO_DIR) + "/eco_marathon_12s.yaml");
  s.bms.protection(bms::FaultId::OverCurrentDischarge).enabled = false;
  s.bms.protection(bms::FaultId::CurrentSensorFault).enabled = false;
  s.load = test::scenarioFromYaml(
               "name: x\npack: {series: 1, cell: {capacity_Ah: 1, ocv_V: 3.5, r0_ohm: 0.01}}\n"
               "load: {segments: [{duration_s: 10, current_A: 10}, {duration_s: 5, current_A: 60}]}\n")
               .load;
  s.run.duration_s = 15.0;
  s.output.interval_s = 0.01;
  const RunResult r = runScenario(s);
  const double blown = test::eventTime(r, "fuse", "blown");
  ASSERT_GE(blown, 0.0);
  // ~1 s at 60 A (the cells sag a little, so the current is what the load asks).
  EXPECT_NEAR(blown - 10.0, fuseBlowTime_s(s.hardware.fuse, 60.0), 0.03);
  for (size_t k = test::sampleAt(r.rec, blown + 0.02); k < r.rec.samples(); ++k)
    ASSERT_EQ(r.rec.pack_current_A[k], 0.0) << "t=" << r.rec.time_s[k];
}

TEST(Relay, OperateAndReleaseDelaysAndWeld) {
  RelayConfig c;
  c.close_delay_s = 0.025;
  c.open_delay_s = 0.010;
  RelayState s;
  relayStep(c, s, true, false, 1.000);
  EXPECT_FALSE(s.closed);
  relayStep(c, s, true, false, 1.020);
  EXPECT_FALSE(s.closed);
  relayStep(c, s, true, false, 1.030);
  EXPECT_TRUE(s.closed);
  relayStep(c, s, false, false, 2.000);
  EXPECT_TRUE(s.closed);
  relayStep(c, s, false, false, 2.010);
  EXPECT_FALSE(s.closed);
  // Welded: once closed it stays closed whatever the coil does.
  relayStep(c, s, true, true, 3.000);
  relayStep(c, s, true, true, 3.030);
  ASSERT_TRUE(s.closed);
  relayStep(c, s, false, true, 4.000);
  relayStep(c, s, false, true, 5.000);
  EXPECT_TRUE(s.closed);
}

}  // namespace
}  // namespace packsim
