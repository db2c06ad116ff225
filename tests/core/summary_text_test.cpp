// Every summary line follows from the run's events and truth (issue 28): each test
// builds the case that would contradict a line and checks the line against the
// relay_contact events, the fault script and the recorded truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/scenario/overrides.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const Event* lastEvent(const RunResult& r, const std::string& kind) {
  const Event* last = nullptr;
  for (const Event& e : r.events)
    if (e.kind == kind) last = &e;
  return last;
}

// The key turned off at 10 s opens the relay; an E-stop at 20 s then latches a trip. The
// contact opened at 10 s and never closed again: no "still closed (welded?)" line.
TEST(SummaryText, TripAfterTheContactOpenedSaysSoAndClaimsNoWeld) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(4) + "load: {current_A: 1}\nrun: {duration_s: 100}\n"
                                            "faults:\n  - {kind: key_off, at_s: 10}\n  - {kind: estop, switch: external, at_s: 20}\n");
  const RunResult r = runScenario(s);
  const std::string text = formatSummary(s, r);
  const Event* opened = lastEvent(r, "relay_contact");
  ASSERT_TRUE(opened && opened->detail == "opened") << text;
  ASSERT_TRUE(r.summary.tripped);
  ASSERT_GT(r.summary.trip_time_s, opened->time_s);
  EXPECT_FALSE(has(text, "welded")) << text;
  char expect[96];
  std::snprintf(expect, sizeof expect, "(estop): the relay contact had opened at %.2f s", opened->time_s);
  EXPECT_TRUE(has(text, expect)) << text;
}

// A welded relay: the contact stays closed after the open command, and the line names
// the injection instead of guessing.
TEST(SummaryText, WeldedContactIsReportedFromTheContactNotTheCommand) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 3}\nrun: {duration_s: 60}\n"
                                            "faults:\n  - {kind: welded_relay, at_s: 0}\n"
                                            "  - {kind: overcurrent, current_A: 40, at_s: 10}\n");
  const RunResult r = runScenario(s);
  const std::string text = formatSummary(s, r);
  const Event* contact = lastEvent(r, "relay_contact");
  ASSERT_TRUE(contact && contact->detail == "closed");
  const Event* command = lastEvent(r, "relay");
  ASSERT_TRUE(command && command->detail == "open");
  EXPECT_TRUE(has(text, "the relay contact stayed closed to the end")) << text;
  char expect[128];
  std::snprintf(expect, sizeof expect, "relay contact still closed at the end, %.2f s after the open command at %.2f s "
                "(welded_relay injected at 0.00 s)", r.summary.duration_s - command->time_s, command->time_s);
  EXPECT_TRUE(has(text, expect)) << text;
}

// An over-current trips at 10.1 s, a reset at 15 s closes the relay again and the load
// runs on: the TRIP line said only "the relay contact opened at 10.11 s", as if the pack
// stayed isolated (found on a 24s4p pack with a reset between two over-currents).
TEST(SummaryText, ARelayClosedAgainAfterTheTripIsOnTheTripLine) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 3}\nrun: {duration_s: 30}\n"
                                            "faults:\n  - {kind: overcurrent, current_A: 40, at_s: 10, duration_s: 1}\n"
                                            "  - {kind: reset_request, at_s: 15}\n");
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.tripped);
  const auto contacts = test::eventsOf(r, "relay_contact");
  ASSERT_EQ(contacts.size(), 3u);  // closed at the start, opened by the trip, closed after the reset
  ASSERT_EQ(contacts[2]->detail, "closed");
  ASSERT_GT(contacts[2]->time_s, 15.0);
  char expect[128];
  std::snprintf(expect, sizeof expect, "(overcurrent_discharge): the relay contact opened at %.2f s; closed again at %.2f s",
                contacts[1]->time_s, contacts[2]->time_s);
  EXPECT_TRUE(has(formatSummary(s, r), expect)) << formatSummary(s, r);
}

// The pack host hangs at 10 s and a 40 A over-current follows at 20 s: nothing trips, as
// nothing decides. The summary said "BMS  no trip" and nothing else (found on a 14s2p
// LTC6811 pack on its charger); the BMS line now says from when the host decided nothing.
TEST(SummaryText, AHungHostIsOnTheBmsLine) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 30}\n"
                                            "faults:\n  - {kind: host_dead, at_s: 10}\n"
                                            "  - {kind: overcurrent, current_A: 40, at_s: 20}\n");
  const RunResult r = runScenario(s);
  ASSERT_FALSE(r.summary.tripped);
  ASSERT_LT(test::eventTime(r, "fault_active", ""), 0.0);  // no BMS fault: none decided
  const std::string text = formatSummary(s, r);
  EXPECT_TRUE(has(text, "BMS             no trip\n                  10.00 s  the pack host's MCU hung (host_dead): no BMS "
                        "decision from then to the end (20.00 s); its outputs held their last levels (the relay contact "
                        "closed then)"))
      << text;
  // A hang of a given length, and none at all: no such line.
  const Scenario sd = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 30}\n"
                                             "faults:\n  - {kind: host_dead, at_s: 10, duration_s: 5}\n");
  EXPECT_TRUE(has(formatSummary(sd, runScenario(sd)), "no BMS decision until 15.00 s (5.00 s)"));
  const Scenario none = test::scenarioFromYaml(test::simpleCellYaml() + test::kSimpleLoadYaml);
  EXPECT_FALSE(has(formatSummary(none, runScenario(none)), "hung"));
}

// System A's host dies at 300 s; its monitor's FAULT line opens the relay on its own. The
// same pack with the FAULT line wired to the MCU only: the contact stays closed, and the
// line must not say the FAULT line opened it.
TEST(SummaryText, FaultLineSaysWhatItIsWiredToAndWhatTheContactDid) {
  const std::string path = test::scenarioDir() + "/faults/a_host_dead.yaml";
  for (const bool opens : {true, false}) {
    const Scenario s = loadScenarioFileWithOverrides(
        path, {{"hardware.afe.fault_line_opens_relay", opens ? "true" : "false"}, {"run.duration_s", "400"}});
    const RunResult r = runScenario(s);
    const std::string text = formatSummary(s, r);
    const double asserted = test::eventTime(r, "monitor_fault_line", "asserted");
    ASSERT_GT(asserted, 0.0) << text;
    const Event* contact = lastEvent(r, "relay_contact");
    ASSERT_NE(contact, nullptr);
    if (opens) {
      EXPECT_EQ(contact->detail, "opened");
      // The BQ76PL455A says why: no valid frame from the dead host within its timeout.
      EXPECT_TRUE(has(text, "monitor FAULT line asserted (it opens the relay without the MCU): device 1: SYS "
                            "(communication timeout: no valid frame from the host within it); the relay contact opened at"))
          << text;
    } else {
      EXPECT_EQ(contact->detail, "closed");
      EXPECT_TRUE(has(text, "monitor FAULT line asserted (it does not drive the relay here): device 1: SYS "
                            "(communication timeout: no valid frame from the host within it); the relay contact stayed "
                            "closed to the end"))
          << text;
      EXPECT_FALSE(has(text, "opens the relay")) << text;
    }
  }
}

// A BQ76952 pack discharging at 57 °C: the part's OTC (55 °C by default; TI judges it
// whether or not a charge flows) latches after its 2 s and asserts the FAULT line. The
// `hardware` line says which protection holds the line, from the part's status
// registers, not only that it went up.
TEST(SummaryText, TheFaultLineSaysWhichProtectionOfThePartHoldsIt) {
  const Scenario s = test::scenarioFromYaml(
      "name: hot_bq\npack: {series: 4, initial_soc: 0.8, initial_temp_C: 57, cell: {preset: ncr18650_3p1Ah}}\n"
      "ambient: {temp_C: 57}\nhardware: {afe: {model: bq76952}, current_sense: {shunt_ohm: 0.001}}\n"
      "bms: {protections: {overtemperature: {threshold_C: 70}}}\n"
      "load: {current_A: 2}\nrun: {duration_s: 10}\n");
  const RunResult r = runScenario(s);
  const double line_s = test::eventTime(r, "monitor_fault_line", "asserted");
  EXPECT_NEAR(line_s, 2.0, 0.1);
  EXPECT_EQ(test::eventTime(r, "monitor_protection", "Safety Status OTC (over-temperature in charge, judged at any current)"),
            line_s);
  const std::string text = formatSummary(s, r);
  EXPECT_TRUE(has(text, "monitor FAULT line asserted (it opens the relay without the MCU): Safety Status OTC "
                        "(over-temperature in charge, judged at any current); the relay contact opened at"))
      << text;
}

// Two laps of a 20 s profile in a 60 s run: the load ends at 40 s. A load_end event and a
// `load` line say so, on both integrators, and the truth agrees: the recorded pack current
// is zero from then on and the charge delivered is the profile's integral from the relay
// closing. The same profile as long as the run (no run.duration_s) has neither.
TEST(SummaryText, ProfileEndingBeforeTheRunIsAnEventAndALine) {
  const std::string profile = test::simpleCellYaml(2) +
                              "load: {segments: [{duration_s: 10, current_A: 2}, {duration_s: 10, current_A: 1}], laps: 2}\n";
  for (const char* solver : {"fast", "cvode"}) {
    SCOPED_TRACE(solver);
    const Scenario s = test::scenarioFromYaml(profile + "run: {duration_s: 60, solver: " + solver + "}\n");
    const RunResult r = runScenario(s);
    const std::string text = formatSummary(s, r);
    ASSERT_FALSE(r.summary.tripped) << text;
    const Event* end = lastEvent(r, "load_end");
    ASSERT_TRUE(end) << text;
    EXPECT_DOUBLE_EQ(end->time_s, 40.0);
    EXPECT_EQ(end->detail, "the load profile ends (2 laps of 20 s): 0 A from here to the run's end");
    EXPECT_TRUE(has(text, "load            the profile ended at 40.00 s; no load for the run's last 20.00 s\n")) << text;
    const Recording& rec = r.rec;
    int during = 0, after = 0;
    for (size_t i = 0; i < rec.samples(); ++i) {
      if (rec.time_s[i] > 40.0) {
        EXPECT_NEAR(rec.pack_current_A[i], 0.0, 1e-9) << rec.time_s[i];
        ++after;
      } else if (rec.time_s[i] > 1.0 && std::fabs(rec.pack_current_A[i]) > 0.5) {
        ++during;
      }
    }
    EXPECT_EQ(after, 20);
    EXPECT_GT(during, 30);
    const double closed_s = test::eventTime(r, "relay_contact", "closed");
    ASSERT_GE(closed_s, 0.0);
    EXPECT_NEAR(3600.0 * r.summary.charge_delivered_Ah, s.load.chargeUntil_As(40.0) - s.load.chargeUntil_As(closed_s), 1e-4);
  }
  const Scenario whole = test::scenarioFromYaml(profile);
  const RunResult r = runScenario(whole);
  EXPECT_DOUBLE_EQ(r.summary.duration_s, 40.0);
  EXPECT_EQ(lastEvent(r, "load_end"), nullptr);
  EXPECT_FALSE(has(formatSummary(whole, r), "\nload ")) << formatSummary(whole, r);
}

// A power profile says watts; a run that stops after a trip before the profile ends has no
// load_end event (the load never ended).
TEST(SummaryText, LoadEndSaysWattsAndIsAbsentWhenATripEndsTheRunFirst) {
  const Scenario power = test::scenarioFromYaml(test::simpleCellYaml(2) +
                                                "load: {points: {time_s: [0, 5], power_W: [4, 4]}}\nrun: {duration_s: 8}\n");
  const RunResult rp = runScenario(power);
  const Event* end = lastEvent(rp, "load_end");
  ASSERT_TRUE(end) << formatSummary(power, rp);
  EXPECT_DOUBLE_EQ(end->time_s, 5.0);
  EXPECT_EQ(end->detail, "the load profile ends (1 lap of 5 s): 0 W from here to the run's end");
  const Scenario tripped = test::scenarioFromYaml(
      test::simpleCellYaml(2) + "load: {segments: [{duration_s: 600, current_A: 1}]}\nrun: {duration_s: 900}\n"
                                "faults:\n  - {kind: estop, switch: external, at_s: 10}\n");
  const RunResult rt = runScenario(tripped);
  ASSERT_TRUE(rt.summary.tripped);
  ASSERT_LT(rt.summary.duration_s, 600.0);
  EXPECT_EQ(lastEvent(rt, "load_end"), nullptr);
}

// A fault scripted after the run stops (60 s after a trip) is an event and a line.
TEST(SummaryText, UnreachedScriptedFaultIsAnEventAndALine) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 3}\nrun: {duration_s: 600}\n"
                                            "faults:\n  - {kind: overcurrent, current_A: 40, at_s: 10}\n"
                                            "  - {kind: hot_cell, cell: 1, heat_W: 5, at_s: 200}\n"
                                            "  - {kind: estop, switch: internal, when: \"cell_min_V < 1.0\"}\n");
  const RunResult r = runScenario(s);
  const std::string text = formatSummary(s, r);
  ASSERT_TRUE(r.summary.tripped);
  ASSERT_LT(r.summary.duration_s, 200.0);
  std::vector<std::string> details;
  for (const Event& e : r.events)
    if (e.kind == "fault_not_reached") {
      EXPECT_DOUBLE_EQ(e.time_s, r.summary.duration_s);
      details.push_back(e.detail);
    }
  ASSERT_EQ(details.size(), 2u) << text;
  EXPECT_TRUE(has(details[0], "hot_cell cell 1, 5 W (line ")) << details[0];
  EXPECT_TRUE(has(details[0], "due at 200.000 s; the run ended at")) << details[0];
  EXPECT_TRUE(has(details[0], ": 60 s after the trip (run.stop_after_trip_s)")) << details[0];
  EXPECT_TRUE(has(details[1], "when cell_min_V < 1.0 never held")) << details[1];
  EXPECT_TRUE(has(text, "fault script    not reached: " + details[0])) << text;
  EXPECT_EQ(test::eventTime(r, "fault_injected", "hot_cell"), -1.0);
}

// A heater on cell 4 of a 4s pack whose only thermistor sits on cell 1: the cell passes the
// 60 C over-temperature limit and the BMS never sees it. The episode's start and maximum
// agree with the recorded truth.
TEST(SummaryText, CellPastALimitUnseenByTheBmsIsReportedWithItsDuration) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(4) + "load: {current_A: 1}\nrun: {duration_s: 400}\n"
                                            "faults:\n  - {kind: hot_cell, cell: 4, heat_W: 8, at_s: 0}\n");
  const RunResult r = runScenario(s);
  const std::string text = formatSummary(s, r);
  EXPECT_FALSE(r.summary.tripped) << text;
  // Truth, from the 1 s recording: the first sample above 60 C by more than half the BMS's
  // 0.1 C reading step (nearer, it reads as the limit), and the maximum.
  const Recording& rec = r.rec;
  double firstAbove = -1.0, maxT = -1e9;
  for (size_t i = 0; i < rec.samples(); ++i) {
    const double T = rec.cell_temp_C[i * 4 + 3];
    if (T > 60.05 && firstAbove < 0.0) firstAbove = rec.time_s[i];
    maxT = std::max(maxT, T);
    for (int c = 0; c < 3; ++c) ASSERT_LT(rec.cell_temp_C[i * 4 + static_cast<size_t>(c)], 60.0);
  }
  ASSERT_GT(firstAbove, 0.0);
  const Event* ev = nullptr;
  for (const Event& e : r.events)
    if (e.kind == "limit_unseen") {
      ASSERT_EQ(ev, nullptr) << "one episode only: " << e.detail;
      ev = &e;
    }
  ASSERT_NE(ev, nullptr) << text;
  EXPECT_TRUE(has(ev->detail, "overtemperature: cell 4 more than 0.05 C above the 60 C limit from ")) << ev->detail;
  EXPECT_TRUE(has(ev->detail, "unseen by the BMS to the end of the run")) << ev->detail;
  const double from_s = std::atof(ev->detail.c_str() + ev->detail.find(" limit from ") + 12);
  EXPECT_GT(from_s, firstAbove - 1.0);
  EXPECT_LE(from_s, firstAbove);
  char maxText[32];
  std::snprintf(maxText, sizeof maxText, "(max %.1f C)", maxT);
  EXPECT_TRUE(has(ev->detail, maxText)) << ev->detail << " vs " << maxT;
  EXPECT_NEAR(r.summary.limit_unseen_longest_s, r.summary.duration_s - from_s, 1e-9);
  EXPECT_TRUE(has(text, "unseen limit    " + ev->detail)) << text;
}

// A 0.2 s pulse takes every cell below the 3.0 V under-voltage limit: the BMS's 500 ms
// debounce ignores it by design, so it is no miss -- no limit_unseen event, no summary
// line (each short excursion was listed for every cell before).
TEST(SummaryText, AnExcursionShorterThanTheProtectionsDelayIsNoMiss) {
  const Scenario s = test::scenarioFromYaml(
      test::simpleCellYaml(2) +
      "bms: {protections: {cell_undervoltage: {threshold_V: 3.0, delay_ms: 500}, "
      "overcurrent_discharge: {threshold_A: 70}}}\n"
      "load: {segments: [{duration_s: 2, current_A: 1}, {duration_s: 0.2, current_A: 60}, "
      "{duration_s: 5, current_A: 1}]}\nrun: {duration_s: 7}\n");
  const RunResult r = runScenario(s);
  EXPECT_LT(r.summary.min_cell_V, 3.0);  // the excursion happened
  EXPECT_FALSE(r.summary.tripped);
  EXPECT_EQ(test::eventTime(r, "limit_unseen"), -1.0);
  EXPECT_FALSE(has(formatSummary(s, r), "unseen limit")) << formatSummary(s, r);
}

// A channel reading 1.5 V low trips the BMS on under-voltage while every cell sits far
// above its v_min: the energy line must not say a cell hit its limit.
TEST(SummaryText, AnUnderVoltageTripIsNotACellAtItsLimit) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml(2) + "load: {current_A: 1}\nrun: {duration_s: 60}\n"
                                            "faults:\n  - {kind: channel_offset, group: 1, offset_mV: -1500, at_s: 5}\n");
  const RunResult r = runScenario(s);
  const std::string text = formatSummary(s, r);
  ASSERT_TRUE(r.summary.tripped) << text;
  EXPECT_EQ(r.summary.trip_reason, "cell_undervoltage");
  EXPECT_GT(r.summary.min_cell_V, s.pack.cell.v_min_V + 0.3);  // the truth never came near v_min
  EXPECT_TRUE(r.summary.limit_by_bms_trip);
  EXPECT_FALSE(has(text, "hit its limit")) << text;
  char expect[96];
  std::snprintf(expect, sizeof expect, "when the BMS tripped on under-voltage at %.2f s (lowest cell ", r.summary.trip_time_s);
  EXPECT_TRUE(has(text, expect)) << text;
}

// In a pack of parallel cells a cell is named with its series group.
TEST(SummaryText, CellsOfParallelGroupsNameTheirGroup) {
  EXPECT_EQ(cellName(74, 4), "cell 74 (group 19)");
  EXPECT_EQ(cellName(73, 4), "cell 73 (group 19)");
  EXPECT_EQ(cellName(77, 4), "cell 77 (group 20)");
  EXPECT_EQ(cellName(5, 1), "cell 5");
  std::string yaml = test::simpleCellYaml(2);
  yaml.replace(yaml.find("  series: 2\n"), 12, "  series: 2\n  parallel: 2\n");
  const Scenario s = test::scenarioFromYaml(yaml + "load: {current_A: 2}\nrun: {duration_s: 400}\n"
                                                   "faults:\n  - {kind: hot_cell, cell: 4, heat_W: 8, at_s: 0}\n");
  const RunResult r = runScenario(s);
  const std::string text = formatSummary(s, r);
  EXPECT_EQ(r.summary.hottest_cell, 4);
  EXPECT_TRUE(has(text, "C  cell 4 (group 2) at ")) << text;
  EXPECT_TRUE(has(text, "unseen limit    overtemperature: cell 4 (group 2) more than 0.05 C above the 60 C limit")) << text;
}

// The SOC-error lines stand under one "SOC error" label whichever estimators ran: a
// firmware that reports the EKF alone gets the label on its one line (the summary's
// lines are rows of a table, summary_text.cpp; the label once belonged to coulomb's).
TEST(SummaryText, SocErrorLabelIsOnTheFirstEstimatorsLine) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 2}\n");
  RunResult r = runScenario(s);
  ASSERT_GT(r.summary.soc_error_coulomb.ticks, 0);
  ASSERT_GT(r.summary.soc_error_ekf.ticks, 0);
  const std::string both = formatSummary(s, r);
  EXPECT_TRUE(has(both, "\nSOC error       coulomb")) << both;
  EXPECT_TRUE(has(both, "\n                ekf")) << both;
  r.summary.soc_error_coulomb.ticks = 0;  // as from a firmware that reports no coulomb count
  const std::string ekfOnly = formatSummary(s, r);
  EXPECT_FALSE(has(ekfOnly, "coulomb")) << ekfOnly;
  EXPECT_TRUE(has(ekfOnly, "\nSOC error       ekf")) << ekfOnly;
  EXPECT_TRUE(has(ekfOnly, "\n                ekf per group: worst ")) << ekfOnly;
}

}  // namespace
}  // namespace packsim
