// Fault scripting: injections start at a time or on a condition, end after their
// duration, act on the plant, and the BMS reaction is measured.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "core/check/check.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// simpleCellYaml: 2 Ah, soc0 0.8, OC-discharge threshold 30 A after 100 ms (default).
TEST(FaultScript, ConditionFiresWhenTheQuantityCrosses) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() +
                                            "load: {current_A: 3}\nrun: {duration_s: 400, stop_after_trip_s: 1}\n"
                                            "output: {interval_s: 0.01}\n"
                                            "faults:\n  - {kind: overcurrent, current_A: 30, when: \"soc < 0.7\"}\n");
  const RunResult r = runScenario(s);
  const double tc = test::eventTime(r, "relay", "close");
  const double cross = tc + 0.1 * 2.0 * 3600.0 / 3.0;  // SOC falls 0.1 at 3 A on 2 Ah
  const double inj = test::eventTime(r, "fault_injected", "overcurrent");
  EXPECT_GE(inj, cross - 1e-6);
  EXPECT_LE(inj, cross + 0.01 + 1e-6);
  // 33 A > 30 A: tripped by the over-current rule after its 100 ms debounce.
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_EQ(r.summary.trip_reason, "overcurrent_discharge");
  EXPECT_NEAR(r.summary.trip_time_s - inj, 0.1, 1e-6);
  const CheckOutcome c = judge(s, r);
  ASSERT_EQ(c.latencies.size(), 1u);
  EXPECT_NE(c.latencies[0].find("overcurrent_discharge after 0.100 s, relay open after 0.100 s"), std::string::npos)
      << c.latencies[0];
}

TEST(FaultScript, TimedInjectionEndsAfterItsDuration) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() +
                                            "load: {current_A: 3}\nrun: {duration_s: 60}\noutput: {interval_s: 0.01}\n"
                                            "faults:\n  - {kind: overcurrent, current_A: 5, at_s: 20, duration_s: 10}\n");
  const RunResult r = runScenario(s);
  EXPECT_NEAR(test::eventTime(r, "fault_injected"), 20.0, 1e-9);
  EXPECT_NEAR(test::eventTime(r, "fault_removed"), 30.0, 1e-9);
  EXPECT_EQ(r.rec.pack_current_A[test::sampleAt(r.rec, 19.99)], 3.0);
  EXPECT_EQ(r.rec.pack_current_A[test::sampleAt(r.rec, 20.0)], 8.0);
  EXPECT_EQ(r.rec.pack_current_A[test::sampleAt(r.rec, 29.99)], 8.0);
  EXPECT_EQ(r.rec.pack_current_A[test::sampleAt(r.rec, 30.0)], 3.0);
  EXPECT_FALSE(r.summary.tripped);
}

// A reset request is a press of the operator's button: the GPIO is asserted for one BMS
// tick (10 ms here) unless `duration_s` says longer; both ends are events. After an
// E-switch pulled for 1 s and released, it is what brings the relay back.
TEST(FaultScript, ResetRequestHoldsTheGpioForOneTick) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() +
                                            "load: {current_A: 1}\nrun: {duration_s: 8, stop_after_trip_s: 100}\n"
                                            "output: {interval_s: 0.01}\n"
                                            "faults:\n  - {kind: estop, switch: internal, at_s: 1, duration_s: 1}\n"
                                            "  - {kind: reset_request, at_s: 3}\n");
  const RunResult r = runScenario(s);
  EXPECT_NEAR(test::eventTime(r, "fault_injected", "reset_request"), 3.0, 1e-9);
  EXPECT_NEAR(test::eventTime(r, "fault_removed", "reset_request"), 3.0 + s.bms.tick_s, 1e-9);
  EXPECT_EQ(r.rec.pack_current_A[test::sampleAt(r.rec, 2.99)], 0.0);  // latched until the reset
  EXPECT_EQ(r.rec.fault_latched[test::sampleAt(r.rec, 8.0)], 0u);
  EXPECT_EQ(r.rec.pack_current_A[test::sampleAt(r.rec, 8.0)], 1.0);   // the relay closed again
}

// A hot cell in a 3-cell chain: the steady temperatures equal the solution of the
// network's linear equations  (G_amb·I + L)·T = q + G_amb·T_amb.
TEST(FaultScript, HotCellReachesTheNetworkSteadyState) {
  const double cth = 10.0, gamb = 0.1, glink = 0.5, q = 2.0, tamb = 20.0;
  const Scenario s = test::scenarioFromYaml(
      "name: hot\nseed: 1\n"
      "pack:\n  series: 3\n  initial_temp_C: 20\n"
      "  cell: {capacity_Ah: 2, ocv_V: 3.7, r0_ohm: 0.02, heat_capacity_J_per_K: 10, g_ambient_W_per_K: 0.1}\n"
      "thermal: {cell_to_cell_W_per_K: 0.5}\nambient: {temp_C: 20}\n"
      "bms: {protections: {overtemperature: {threshold_C: 100}}}\n"
      "load: {current_A: 0}\nrun: {duration_s: 3000}\n"
      "faults:\n  - {kind: hot_cell, cell: 2, heat_W: 2, at_s: 0}\n");
  const RunResult r = runScenario(s);
  Eigen::Matrix3d A;
  A << gamb + glink, -glink, 0, -glink, gamb + 2 * glink, -glink, 0, -glink, gamb + glink;
  const Eigen::Vector3d b(gamb * tamb, q + gamb * tamb, gamb * tamb);
  const Eigen::Vector3d T = A.colPivHouseholderQr().solve(b);
  const size_t last = r.rec.samples() - 1;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.rec.cell_temp_C[last * 3 + static_cast<size_t>(c)], T(c), 1e-4) << c;
  EXPECT_GT(T(1), T(0) + 1.0);  // the hot cell is the hottest, its neighbours follow
  (void)cth;
}

TEST(FaultScript, InternalShortDrainsOnlyThatCell) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(3) +
                                            "load: {current_A: 0}\nrun: {duration_s: 3600}\n"
                                            "faults:\n  - {kind: internal_short, cell: 2, resistance_ohm: 10, at_s: 0}\n");
  const RunResult r = runScenario(s);
  const size_t last = (r.rec.samples() - 1) * 3;
  EXPECT_DOUBLE_EQ(r.rec.cell_soc[last + 0], 0.8);
  EXPECT_DOUBLE_EQ(r.rec.cell_soc[last + 2], 0.8);
  // About OCV/R = 4.04/10 A for an hour out of 2 Ah: SOC falls by ~0.2.
  EXPECT_NEAR(0.8 - r.rec.cell_soc[last + 1], 0.2, 0.01);
}

}  // namespace
}  // namespace packsim

namespace packsim {
namespace {

// The fault_injected event gives each value as written, with its own sign: a charging
// over-current read "overcurrent +-30 A" (found on a 24s4p pack), a drift of 1000 A/h
// "+1e+03 A/h", 12.345 A "+12.3 A".
TEST(FaultScript, AnInjectionsEventGivesItsValuesAsWritten) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 2}\n"
                                            "faults:\n  - {kind: overcurrent, current_A: -30, at_s: 0.5}\n"
                                            "  - {kind: overcurrent, current_A: 12.345, at_s: 0.5}\n"
                                            "  - {kind: current_sensor_drift, offset_A: -0.5, drift_A_per_h: 1000, at_s: 0.5}\n"
                                            "  - {kind: hot_cell, cell: 1, heat_W: 1250, at_s: 0.5}\n");
  ASSERT_EQ(s.faults.size(), 4u);
  EXPECT_EQ(s.faults[0].describe(), "overcurrent -30 A");
  EXPECT_EQ(s.faults[1].describe(), "overcurrent +12.345 A");
  EXPECT_EQ(s.faults[2].describe(), "current_sensor_drift -0.5 A +1000 A/h");
  EXPECT_EQ(s.faults[3].describe(), "hot_cell cell 1, 1250 W");
}

}  // namespace
}  // namespace packsim
