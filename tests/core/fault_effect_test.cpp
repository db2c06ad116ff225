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
  noteEffect(cv, p, off);
  EXPECT_TRUE(off.acted);

  FaultInjection hot;
  hot.kind = FaultKind::HotCell;
  EXPECT_FALSE(needsCurrentPath(hot));
}

}  // namespace
}  // namespace packsim
