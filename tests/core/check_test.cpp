// Scenarios as tests: an unmet expectation fails with a message; a batch with a
// broken scenario still runs the others and reports the failure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "core/check/check.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/stranded_energy.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

const std::string kTripping = "load: {current_A: 3}\nrun: {duration_s: 60}\n"
                              "faults:\n  - {kind: overcurrent, current_A: 40, at_s: 10}\n";

TEST(Check, UnmetExpectationsFailWithReasons) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + kTripping +
                                            "expect: {no_trip: true, max_temp_C_below: 20}\n");
  const CheckOutcome c = judge(s, runScenario(s));
  EXPECT_FALSE(c.passed);
  ASSERT_EQ(c.failures.size(), 2u);
  EXPECT_NE(c.failures[0].find("expected no trip, but the BMS tripped at 10.100 s (overcurrent_discharge): the relay "
                               "contact opened at 10.10 s"),
            std::string::npos)
      << c.failures[0];
  EXPECT_NE(c.failures[1].find("is not below 20.00 C"), std::string::npos) << c.failures[1];
}

// A trip whose relay contact never opened (welded here) is no isolation: the no-trip
// failure says what the contact did instead of "the relay opened", and a passing check
// warns. (Found with a user's firmware that tripped without opening the relay.)
TEST(Check, ATripThatDidNotIsolateIsSaidSo) {
  const std::string welded = test::simpleCellYaml() + kTripping + "  - {kind: welded_relay, at_s: 0}\n";
  const Scenario s = test::scenarioFromYaml(welded + "expect: {no_trip: true}\n");
  const CheckOutcome c = judge(s, runScenario(s));
  ASSERT_EQ(c.failures.size(), 1u);
  EXPECT_NE(c.failures[0].find("expected no trip, but the BMS tripped at 10.100 s (overcurrent_discharge): the relay "
                               "contact stayed closed to the end"),
            std::string::npos)
      << c.failures[0];
  const Scenario p = test::scenarioFromYaml(welded + "expect: {trip_reason: overcurrent_discharge}\n");
  const CheckOutcome d = judge(p, runScenario(p));
  EXPECT_TRUE(d.passed);
  const auto isolation = [](const CheckOutcome& o) {
    return std::count_if(o.warnings.begin(), o.warnings.end(),
                         [](const std::string& w) { return w.find("did not isolate") != std::string::npos; });
  };
  EXPECT_EQ(isolation(d), 1);
  EXPECT_NE(std::find(d.warnings.begin(), d.warnings.end(),
                      "the BMS tripped at 10.100 s (overcurrent_discharge) but the relay contact stayed closed to the "
                      "end: the trip did not isolate the pack"),
            d.warnings.end());
  const Scenario ok = test::scenarioFromYaml(test::simpleCellYaml() + kTripping);
  EXPECT_EQ(isolation(judge(ok, runScenario(ok))), 0) << "a trip that opened the contact: no warning";
}

TEST(Check, MetExpectationsPass) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + kTripping +
                                            "expect:\n  trip_reason: overcurrent_discharge\n  trip_within_s: [10.1, 10.11]\n"
                                            "  relay_open_by_s: 10.11\n"
                                            "  detected: [{fault: overcurrent_discharge, within_s: [10.1, 10.11]}]\n");
  const CheckOutcome c = judge(s, runScenario(s));
  EXPECT_TRUE(c.passed) << (c.failures.empty() ? "" : c.failures[0]);
}

TEST(Check, CliReportsEveryScenarioAndFailsTheBatch) {
  const fs::path dir = test::processTempDir("packsim_check_cli");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "a_good.yaml") << test::simpleCellYaml() << "load: {current_A: 1}\nrun: {duration_s: 5}\nexpect: {no_trip: true}\n";
  std::ofstream(dir / "b_broken.yaml") << "name: broken\npack: {series: 1}\n";
  std::ofstream(dir / "c_wrong.yaml") << test::simpleCellYaml() << kTripping << "expect: {no_trip: true}\n";
  const std::string out = (dir / "out.txt").string();
  const int rc = std::system((std::string(PACKSIM_BINARY) + " check " + dir.string() + " > " + out).c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 1);
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("PASS  " + (dir / "a_good.yaml").string()), std::string::npos) << text;
  EXPECT_NE(text.find("ERROR " + (dir / "b_broken.yaml").string()), std::string::npos) << text;
  EXPECT_NE(text.find("missing required key 'cell'"), std::string::npos) << text;
  EXPECT_NE(text.find("FAIL  " + (dir / "c_wrong.yaml").string()), std::string::npos) << text;
  EXPECT_NE(text.find("1 passed, 2 failed"), std::string::npos) << text;
  fs::remove_all(dir);
}

// A check that passes still shows what the loader and the run found questionable: the
// same config warnings `packsim run` prints (they were printed by `run` alone). A 2 ms
// tick cannot hold the read-out of ten BQ76PL536A devices: the run warns that it read
// every 4 ms, and the check says so under its PASS line.
TEST(Check, PrintsTheRunsConfigWarnings) {
  const fs::path dir = test::processTempDir("packsim_check_warn");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "warned.yaml")
      << "name: warned\npack:\n  series: 60\n  cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}\n"
         "hardware:\n  afe: {model: bq76pl536a}\nbms: {tick_ms: 2}\nload: {current_A: 1}\nrun: {duration_s: 1}\n"
         "expect: {no_trip: true}\n";
  const CheckOutcome c = checkScenarioFile((dir / "warned.yaml").string());
  EXPECT_TRUE(c.passed);
  bool readout = false;
  for (const std::string& w : c.warnings) readout = readout || w.find("bms.readout.period_ms = 4") == 0;
  EXPECT_TRUE(readout) << c.warnings.size() << " warnings";
  const std::string out = (dir / "out.txt").string();
  const int rc = std::system((std::string(PACKSIM_BINARY) + " check " + (dir / "warned.yaml").string() + " > " + out).c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 0);
  std::ifstream in(out);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("      warning: bms.readout.period_ms = 4 (default"), std::string::npos) << text;
  fs::remove_all(dir);
}

// A hot cell injected at 300 s (too little heat to reach a limit) and an E-stop at 450 s:
// the E-stop is not credited to the hot cell (it was: "estop after 150.000 s").
TEST(Check, EachDetectionIsCreditedToTheInjectionThatCanCauseIt) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 600}\n"
                                            "faults:\n  - {kind: hot_cell, cell: 1, heat_W: 0.5, at_s: 300}\n"
                                            "  - {kind: estop, switch: external, at_s: 450}\n");
  const RunResult r = runScenario(s);
  const CheckOutcome c = judge(s, r);
  ASSERT_EQ(c.fault_latencies.size(), 2u);
  ASSERT_EQ(c.latencies.size(), 2u);
  const FaultLatency& hot = c.fault_latencies[0];
  EXPECT_EQ(hot.detected_fault, "");
  EXPECT_LT(hot.detection_latency_s, 0.0);
  EXPECT_LT(hot.relay_open_latency_s, 0.0);
  EXPECT_EQ(c.latencies[0].find("estop after"), std::string::npos) << c.latencies[0];
  EXPECT_NE(c.latencies[0].find("no BMS fault it can cause"), std::string::npos) << c.latencies[0];
  EXPECT_NE(c.latencies[0].find("(estop at 450.000 s is not caused by it)"), std::string::npos) << c.latencies[0];
  EXPECT_NE(c.latencies[0].find("relay opened at 450.000 s but not on a fault this injection causes"), std::string::npos)
      << c.latencies[0];
  const FaultLatency& estop = c.fault_latencies[1];
  EXPECT_EQ(estop.detected_fault, "estop");
  EXPECT_NEAR(estop.detection_latency_s, 0.0, 1e-9);
  EXPECT_GE(estop.relay_open_latency_s, 0.0);
}

// The hot cell that does reach the limit is credited with the over-temperature, even
// when an unrelated fault (an E-stop that does not latch: monitor only) came first.
TEST(Check, TheCausingFaultIsFoundPastAnUnrelatedOne) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 900}\n"
                                            "bms: {protections: {estop: {action: monitor}}}\n"
                                            "faults:\n  - {kind: hot_cell, cell: 1, heat_W: 8, at_s: 10}\n"
                                            "  - {kind: estop, switch: external, at_s: 20, duration_s: 5}\n");
  const RunResult r = runScenario(s);
  const CheckOutcome c = judge(s, r);
  ASSERT_EQ(c.fault_latencies.size(), 2u);
  const double ot = test::eventTime(r, "fault_active", "overtemperature");
  ASSERT_GT(ot, 20.0);
  EXPECT_EQ(c.fault_latencies[0].detected_fault, "overtemperature") << c.latencies[0];
  EXPECT_NEAR(c.fault_latencies[0].detection_latency_s, ot - 10.0, 1e-9);
}

// A 50 ms over-current (shorter than the 100 ms debounce) that tripped nothing, then a
// lasting one at 20 s: the trip at 20.1 s is the second's alone. It was credited to the
// first as well ("overcurrent_discharge after 10.100 s"), found on a 24s4p pack with
// three over-currents and a reset between them.
TEST(Check, AFaultAfterAnInjectionEndedIsALaterInjectionsOfTheSameKind) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 3}\nrun: {duration_s: 30}\n"
                                            "faults:\n  - {kind: overcurrent, current_A: 40, at_s: 10, duration_s: 0.05}\n"
                                            "  - {kind: overcurrent, current_A: 40, at_s: 20}\n");
  const RunResult r = runScenario(s);
  const double trip = test::eventTime(r, "fault_active", "overcurrent_discharge");
  ASSERT_NEAR(trip, 20.1, 1e-9);  // the first never tripped: one over-current, at the second
  const CheckOutcome c = judge(s, r);
  ASSERT_EQ(c.fault_latencies.size(), 2u);
  EXPECT_EQ(c.fault_latencies[0].detected_fault, "") << c.latencies[0];
  EXPECT_LT(c.fault_latencies[0].detection_latency_s, 0.0);
  EXPECT_LT(c.fault_latencies[0].relay_open_latency_s, 0.0);
  EXPECT_NE(c.latencies[0].find("no BMS fault it can cause"), std::string::npos) << c.latencies[0];
  EXPECT_NE(c.latencies[0].find("(removed at 10.050 s; overcurrent_discharge at 20.100 s followed overcurrent +40 A "
                                "injected at 20.000 s)"),
            std::string::npos)
      << c.latencies[0];
  EXPECT_EQ(c.fault_latencies[1].detected_fault, "overcurrent_discharge");
  EXPECT_NEAR(c.fault_latencies[1].detection_latency_s, trip - 20.0, 1e-9);
}

// Two hot cells at once: neither can be told from the other, so both keep the
// over-temperature (the rule above takes a fault from an injection only once it has ended).
TEST(Check, OverlappingInjectionsBothKeepTheFault) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 900}\n"
                                            "faults:\n  - {kind: hot_cell, cell: 1, heat_W: 8, at_s: 10}\n"
                                            "  - {kind: hot_cell, cell: 1, heat_W: 1, at_s: 20}\n");
  const RunResult r = runScenario(s);
  const CheckOutcome c = judge(s, r);
  ASSERT_EQ(c.fault_latencies.size(), 2u);
  EXPECT_EQ(c.fault_latencies[0].detected_fault, "overtemperature") << c.latencies[0];
  EXPECT_EQ(c.fault_latencies[1].detected_fault, "overtemperature") << c.latencies[1];
}

// An open thermistor at 20 s, after an over-current trip had opened the relay at 10 s: the
// thermistor fault "did not open the relay" (it said "relay not opened", as if the BMS had
// failed to act); the contact was open already. Found on a 14s2p LTC6811 pack.
TEST(Check, AFaultRaisedWithTheRelayAlreadyOpenSaysSo) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 3}\nrun: {duration_s: 30}\n"
                                            "faults:\n  - {kind: overcurrent, current_A: 40, at_s: 10, duration_s: 1}\n"
                                            "  - {kind: thermistor_open, thermistor: 1, at_s: 20}\n");
  const RunResult r = runScenario(s);
  const auto contacts = test::eventsOf(r, "relay_contact");
  ASSERT_EQ(contacts.size(), 2u);  // closed at the start, opened by the trip
  ASSERT_EQ(contacts[1]->detail, "opened");
  ASSERT_LT(contacts[1]->time_s, 11.0);
  const CheckOutcome c = judge(s, r);
  ASSERT_EQ(c.fault_latencies.size(), 2u);
  EXPECT_EQ(c.fault_latencies[1].detected_fault, "thermistor_fault") << c.latencies[1];
  EXPECT_LT(c.fault_latencies[1].relay_open_latency_s, 0.0);
  char expect[64];
  std::snprintf(expect, sizeof expect, ", relay already open (since %.3f s)", contacts[1]->time_s);
  EXPECT_NE(c.latencies[1].find(expect), std::string::npos) << c.latencies[1];
}

// An expected injection the run never reached (it stopped 60 s after an earlier trip)
// fails the check with that reason.
TEST(Check, UnreachedScriptedFaultFails) {
  const Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + kTripping.substr(0, kTripping.find("run:")) +
                                            "run: {duration_s: 600}\nfaults:\n"
                                            "  - {kind: overcurrent, current_A: 40, at_s: 10}\n"
                                            "  - {kind: hot_cell, cell: 1, heat_W: 5, at_s: 300}\n"
                                            "expect: {trip_reason: overcurrent_discharge}\n");
  const CheckOutcome c = judge(s, runScenario(s));
  EXPECT_FALSE(c.passed);
  ASSERT_EQ(c.failures.size(), 1u);
  EXPECT_NE(c.failures[0].find("scripted fault never happened: hot_cell cell 1, 5 W"), std::string::npos) << c.failures[0];
  EXPECT_NE(c.failures[0].find("due at 300.000 s"), std::string::npos) << c.failures[0];
  EXPECT_NE(c.verdict.find("1 scripted fault not reached"), std::string::npos) << c.verdict;
}

// With a constant OCV the energy of a cell is Q·OCV·SOC, so the stranded energy is
// exactly Q·OCV·(SOC_i - SOC_weakest) summed.
TEST(StrandedEnergy, ConstantOcvIsExact) {
  Pack p;
  p.series = 3;
  CellParams c;
  c.capacity_Ah = 2.0;
  c.ocv_V = Curve::constant(3.7);
  p.cells = {c, c, c};
  p.cells[2].capacity_Ah = 3.0;
  const StrandedEnergy e = strandedEnergy(p, {0.1, 0.3, 0.2}, 0);
  EXPECT_NEAR(e.left_Wh, 3.7 * (2 * 0.1 + 2 * 0.3 + 3 * 0.2), 1e-9);
  EXPECT_NEAR(e.stranded_Wh, 3.7 * (2 * 0.2 + 3 * 0.1), 1e-9);
}

}  // namespace
}  // namespace packsim
