// A scripted fault that needs the current path and never had it is a `fault_no_effect`
// event, a `fault script` summary line and a `check` failure (core/sim/fault_effect.hpp).
// Each case is checked against what the run did: the relay_contact events and the
// recorded pack current.
#include <gtest/gtest.h>

#include <cmath>

#include "core/check/check.hpp"
#include "core/scenario/overrides.hpp"
#include "core/sim/fault_effect.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

Scenario withFaults(const std::string& faults, double duration_s = 60.0) {
  return test::scenarioFromYaml(test::simpleCellYaml(2) + "load: {current_A: 1}\nrun: {duration_s: " +
                                std::to_string(duration_s) + "}\nfaults:\n" + faults);
}

// The largest recorded |pack current| in [t0, t1].
double peakCurrent(const RunResult& r, double t0, double t1) {
  double peak = 0.0;
  for (size_t i = 0; i < r.rec.time_s.size(); ++i)
    if (r.rec.time_s[i] >= t0 && r.rec.time_s[i] <= t1) peak = std::max(peak, std::abs(r.rec.pack_current_A[i]));
  return peak;
}

// The key off at 10 s opens the relay; a weld scripted at 20 s finds it open and the BMS
// never closes it again: the weld had nothing to hold.
TEST(FaultEffect, WeldOfAnOpenRelayHasNoEffect) {
  const Scenario s = withFaults("  - {kind: key_off, at_s: 10}\n  - {kind: welded_relay, at_s: 20}\n");
  const RunResult r = runScenario(s);
  const auto opened = test::eventsOf(r, "relay_contact");
  ASSERT_FALSE(opened.empty());
  ASSERT_EQ(opened.back()->detail, "opened");
  ASSERT_LT(opened.back()->time_s, 20.0);
  const auto none = test::eventsOf(r, "fault_no_effect");
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0]->detail,
            "welded_relay (line 23, active from 20.000 s to the end): the relay contact was open the whole time: a weld "
            "holds a closed contact, and the relay never closed while welded");
  EXPECT_DOUBLE_EQ(none[0]->time_s, r.summary.duration_s);
  EXPECT_TRUE(has(formatSummary(s, r), "fault script    no effect: " + none[0]->detail)) << formatSummary(s, r);
}

// Welded at 5 s while closed, and the BMS never commands it open: the weld never showed.
// Then the same weld with the key off at 10 s: the contact stays closed against the
// command, and no fault_no_effect event.
TEST(FaultEffect, WeldNeverCommandedOpenIsNotTestedAndOneCommandedOpenActs) {
  const RunResult idle = runScenario(withFaults("  - {kind: welded_relay, at_s: 5}\n"));
  ASSERT_FALSE(idle.summary.tripped);
  const auto none = test::eventsOf(idle, "fault_no_effect");
  ASSERT_EQ(none.size(), 1u);
  EXPECT_TRUE(has(none[0]->detail, "the relay was never commanded open while welded")) << none[0]->detail;

  const Scenario s = withFaults("  - {kind: welded_relay, at_s: 5}\n  - {kind: key_off, at_s: 10}\n");
  const RunResult held = runScenario(s);
  EXPECT_TRUE(test::eventsOf(held, "fault_no_effect").empty());
  const auto contact = test::eventsOf(held, "relay_contact");
  ASSERT_FALSE(contact.empty());
  EXPECT_EQ(contact.back()->detail, "closed");  // held against the key-off's open command
  EXPECT_GT(test::eventTime(held, "relay", "open"), 10.0 - 1e-9);
}

// An over-current scripted while the relay stands open (key off) adds nothing: the
// recorded pack current stays 0 A through it. The same over-current with the relay
// closed flows, and is no fault_no_effect event.
TEST(FaultEffect, OvercurrentWithTheRelayOpenHasNoEffect) {
  const Scenario s = withFaults("  - {kind: key_off, at_s: 5}\n  - {kind: overcurrent, current_A: 4, at_s: 20, duration_s: 10}\n");
  const RunResult r = runScenario(s);
  EXPECT_EQ(peakCurrent(r, 20.0, 30.0), 0.0);
  const auto none = test::eventsOf(r, "fault_no_effect");
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0]->detail,
            "overcurrent +4 A (line 23, active 20.000-30.000 s): no extra current flowed: the relay contact was open (or "
            "the fuse blown) the whole time");

  const RunResult flowing = runScenario(withFaults("  - {kind: overcurrent, current_A: 4, at_s: 20, duration_s: 10}\n"));
  EXPECT_NEAR(peakCurrent(flowing, 21.0, 29.0), 5.0, 1e-9);
  EXPECT_TRUE(test::eventsOf(flowing, "fault_no_effect").empty());
}

// A fault an override wrote has no line in the file: the event names its place in the list.
TEST(FaultEffect, AnOverriddenFaultIsNamedByItsPlaceInTheList) {
  const std::string text = test::simpleCellYaml(2) + "load: {current_A: 1}\nrun: {duration_s: 30}\n";
  const Scenario s = loadScenarioWithOverrides(text, {{"faults", "[{kind: key_off, at_s: 2}, {kind: welded_relay, at_s: 5}]"}});
  const RunResult r = runScenario(s);
  const auto none = test::eventsOf(r, "fault_no_effect");
  ASSERT_EQ(none.size(), 1u);
  EXPECT_TRUE(has(none[0]->detail, "welded_relay (faults[1], set by an override, active from 5.000 s to the end)"))
      << none[0]->detail;
}

// A regression test whose scripted fault had no effect tests nothing: check fails it.
TEST(FaultEffect, CheckFailsAScenarioWhoseFaultHadNoEffect) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(2) +
                                            "load: {current_A: 1}\nrun: {duration_s: 40}\n"
                                            "faults:\n  - {kind: key_off, at_s: 10}\n  - {kind: welded_relay, at_s: 20}\n"
                                            "expect: {no_trip: true}\n");
  const CheckOutcome o = judge(s, runScenario(s));
  EXPECT_FALSE(o.passed);
  bool named = false;
  for (const std::string& f : o.failures) named = named || has(f, "scripted fault had no effect: welded_relay");
  EXPECT_TRUE(named);
  EXPECT_TRUE(has(o.verdict, "1 scripted fault without effect")) << o.verdict;
}

// A 2-cell pack on a CC-CV charger (8.4 V, 2 A). A charger overvoltage during the CC
// phase (the terminal voltage some 8.25 V) leaves the charger current-limited: the
// recorded current is the run's without it, and the run says so. The same
// overvoltage in the CV phase raises the current the charger delivers, and is no
// fault_no_effect. (It was none in both: the charger was on, so the fault counted as acted.)
TEST(FaultEffect, ChargerOvervoltageWhileCurrentLimitedHasNoEffect) {
  const std::string base = test::simpleCellYaml(2) +
                           "load: {charger: {current_A: 2, voltage_V: 8.4, end_current_A: 0.1}}\n"
                           "run: {duration_s: 700}\n";
  const RunResult clean = runScenario(test::scenarioFromYaml(base));
  const Scenario s = test::scenarioFromYaml(base +
                                            "faults:\n  - {kind: charger_overvoltage, overvoltage_V: 0.05, at_s: 10, "
                                            "duration_s: 100}\n");
  const RunResult cc = runScenario(s);
  ASSERT_EQ(cc.rec.samples(), clean.rec.samples());
  // Equal while the fault is active; after it, the integrator's restarts at 10 and 110 s
  // leave differences within its tolerance (where the taper starts, ~1e-4 A).
  for (size_t i = 0; i < cc.rec.samples(); ++i) {
    if (cc.rec.time_s[i] <= 110.0) ASSERT_EQ(cc.rec.pack_current_A[i], clean.rec.pack_current_A[i]) << i;
    ASSERT_NEAR(cc.rec.pack_current_A[i], clean.rec.pack_current_A[i], 1e-3) << i;
  }
  const auto none = test::eventsOf(cc, "fault_no_effect");
  ASSERT_EQ(none.size(), 1u);
  EXPECT_TRUE(has(none[0]->detail, "charger_overvoltage +0.05 V (line 22, active 10.000-110.000 s): the charger stayed "
                                   "current-limited (CC) the whole time"))
      << none[0]->detail;
  EXPECT_TRUE(has(none[0]->detail, "below the charger's own setpoint of 8.400 V")) << none[0]->detail;
  EXPECT_TRUE(has(formatSummary(s, cc), "fault script    no effect: " + none[0]->detail));

  const RunResult cv = runScenario(test::scenarioFromYaml(
      base + "faults:\n  - {kind: charger_overvoltage, overvoltage_V: 0.05, at_s: 500, duration_s: 100}\n"));
  EXPECT_TRUE(test::eventsOf(cv, "fault_no_effect").empty());
  ASSERT_EQ(cv.rec.samples(), clean.rec.samples());
  double moreCharge_A = 0.0;  // the raised setpoint holds the charge current above the clean run's
  for (size_t i = 0; i < cv.rec.samples(); ++i)
    if (cv.rec.time_s[i] > 510.0 && cv.rec.time_s[i] < 600.0)
      moreCharge_A = std::max(moreCharge_A, clean.rec.pack_current_A[i] - cv.rec.pack_current_A[i]);
  EXPECT_GT(moreCharge_A, 0.1);
}

// Cell 1 starts at SOC 0.97, cell 2 at 0.8: on the 8.4 V charger cell 1 trips
// cell_overvoltage at 65.7 s with the pack at 8.37 V, below the charger's own setpoint, so
// a charger overvoltage from 5 s changed nothing. check's line for the injection credited it
// with that trip ("cell_overvoltage after 60.690 s, relay open after 60.690 s") beside the
// failure saying it had no effect; it now says it had none, and its latency names no fault.
TEST(FaultEffect, CheckCreditsNoDetectionToAFaultWithoutEffect) {
  std::string yaml = test::simpleCellYaml(2);
  yaml.insert(yaml.find("  cell:\n"), "  cells:\n    - {cell: 1, initial_soc: 0.97}\n");
  const Scenario s = test::scenarioFromYaml(yaml +
                                            "load: {charger: {current_A: 2, voltage_V: 8.4, end_current_A: 0.1}}\n"
                                            "run: {duration_s: 600}\n"
                                            "faults:\n  - {kind: charger_overvoltage, overvoltage_V: 0.5, at_s: 5}\n"
                                            "expect: {trip_reason: cell_overvoltage}\n");
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.tripped);
  ASSERT_EQ(r.summary.trip_reason, "cell_overvoltage");
  ASSERT_EQ(test::eventsOf(r, "fault_no_effect").size(), 1u);
  const CheckOutcome o = judge(s, r);
  ASSERT_EQ(o.latencies.size(), 1u);
  EXPECT_TRUE(has(o.latencies[0], "charger_overvoltage +0.5 V @5.000 s: no effect: the charger stayed current-limited"))
      << o.latencies[0];
  EXPECT_FALSE(has(o.latencies[0], "cell_overvoltage after")) << o.latencies[0];
  ASSERT_EQ(o.fault_latencies.size(), 1u);
  EXPECT_EQ(o.fault_latencies[0].detected_fault, "");
  EXPECT_LT(o.fault_latencies[0].detection_latency_s, 0.0);
  EXPECT_LT(o.fault_latencies[0].relay_open_latency_s, 0.0);
}

// The rule per kind: an extra charge current needs the charge direction, a charger's
// overvoltage a connected charger; other kinds always act.
TEST(FaultEffect, EachKindNeedsItsOwnPath) {
  FaultInjection oc;
  oc.kind = FaultKind::Overcurrent;
  oc.value = -3.0;  // into the pack
  PathState p;
  p.relayContactClosed = p.mainClosed = true;
  p.chargeBlocked = true;
  EffectSeen seen;
  noteEffect(oc, p, seen);
  EXPECT_FALSE(seen.acted);
  EXPECT_TRUE(has(noEffectText(oc, seen), "the FETs (or a blown fuse) blocked its direction"));
  p.chargeBlocked = false;
  p.dischargeBlocked = true;
  noteEffect(oc, p, seen);
  EXPECT_TRUE(seen.acted);

  FaultInjection cv;
  cv.kind = FaultKind::ChargerOvervoltage;
  EffectSeen off;
  p = PathState{};
  p.mainClosed = p.relayContactClosed = true;
  noteEffect(cv, p, off);
  EXPECT_FALSE(off.acted);  // the charger is off
  p.chargerOn = true;
  p.chargerSetpoint_V = 8.4;
  p.terminal_V = 8.3;  // current-limited: a raised setpoint changes nothing
  noteEffect(cv, p, off);
  EXPECT_FALSE(off.acted);
  EXPECT_TRUE(has(noEffectText(cv, off), "peaked at 8.300 V, below the charger's own setpoint of 8.400 V"))
      << noEffectText(cv, off);
  p.terminal_V = 8.41;  // above its own setpoint: a sound charger would cut the current
  noteEffect(cv, p, off);
  EXPECT_TRUE(off.acted);

  FaultInjection hot;
  hot.kind = FaultKind::HotCell;
  EXPECT_FALSE(needsCurrentPath(hot));
}

}  // namespace
}  // namespace packsim
