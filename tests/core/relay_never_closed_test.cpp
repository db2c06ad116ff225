// A run whose relay never closed while its load asked for current (core/sim/summary_text.hpp,
// relayNeverClosed): "BMS no trip" and 0 Wh out said nothing about why; the summary's
// `relay` line and a `check` warning say the relay never closed, what the load asked,
// what it drew and the BMS's last state. Built on the run that would contradict each
// part: run_request false (standby), a power profile (W), a charger, and an ordinary
// run (no line).
#include <gtest/gtest.h>

#include <algorithm>

#include "core/check/check.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::string relayLine(const std::string& text) {
  const size_t at = text.find("\nrelay ");
  return at == std::string::npos ? "" : text.substr(at + 1, text.find('\n', at + 1) - at - 1);
}

TEST(RelayNeverClosed, ARunRequestNeverGivenLeavesTheLoadUnservedAndSaysSo) {
  const Scenario s = test::scenarioFromYaml("extends: bench_6s_ncr18650_2C.yaml\nbms: {run_request: false}\nrun: {duration_s: 20}\n");
  const RunResult r = runScenario(s);
  EXPECT_FALSE(r.summary.tripped);
  EXPECT_EQ(test::eventTime(r, "relay_contact", "closed"), -1.0);
  EXPECT_EQ(r.summary.charge_delivered_Ah, 0.0);
  EXPECT_FALSE(r.summary.relay_closed);
  const std::string line = relayLine(formatSummary(s, r));
  // The bundled bench discharge is 2C of a 3.1 Ah cell: 5.9 A (its file says so).
  EXPECT_EQ(line, "relay           never closed in the run's 20.00 s: the load asked for up to 5.90 A discharge and drew "
                  "0.000 Ah; the BMS's last state: standby");
  const CheckOutcome c = judge(s, r);
  EXPECT_NE(std::find(c.warnings.begin(), c.warnings.end(), "the relay " + line.substr(16)), c.warnings.end());
}

TEST(RelayNeverClosed, APowerProfileIsNamedInWattsAndAChargerByItsCurrent) {
  const Scenario p = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\nbms: {run_request: false}\nload: {segments: [{duration_s: 5, power_W: 40}, "
      "{duration_s: 5, power_W: -12.5}]}\nrun: {duration_s: 10}\n");
  EXPECT_NE(relayLine(formatSummary(p, runScenario(p))).find("up to 40.00 W discharge, 12.50 W regeneration and drew"),
            std::string::npos);
  // A charger the BMS is not told of (charger_present false, no run request): it never closes for it.
  const Scenario c = test::scenarioFromYaml(
      "extends: bench_6s_ncr18650_2C.yaml\npack: {initial_soc: 0.5}\nbms: {run_request: false, charger_present: false}\n"
      "load: {charger: {current_A: 1.5, voltage_V: 25.2}}\nrun: {duration_s: 10}\n");
  const RunResult rc = runScenario(c);
  ASSERT_LT(test::eventTime(rc, "relay_contact", "closed"), 0.0);
  EXPECT_NE(relayLine(formatSummary(c, rc)).find("up to 1.50 A from the charger and drew"), std::string::npos)
      << formatSummary(c, rc);
}

// A user's firmware keeps its own state: the example firmware without a run request
// waits in its STANDBY (its telemetry's first byte, 0), while packsim's bms_state
// channel stays at its first value. The line named "the BMS's last state: init"; it
// names no state of packsim's core for a firmware that is not packsim's core.
TEST(RelayNeverClosed, AUserFirmwaresStateIsNotNamedFromPacksimsCore) {
  const Scenario s = test::scenarioFromYaml("extends: firmware/c_example_firmware.yaml\nbms: {run_request: false}\n"
                                            "run: {duration_s: 2}\n");
  const RunResult r = runScenario(s);
  ASSERT_EQ(r.summary.charge_delivered_Ah, 0.0);
  EXPECT_EQ(relayLine(formatSummary(s, r)),
            "relay           never closed in the run's 2.00 s: the load asked for up to 5.90 A discharge and drew "
            "0.000 Ah");
}

TEST(RelayNeverClosed, AnOrdinaryRunHasNoRelayLine) {
  const Scenario s = test::scenarioFromYaml("extends: bench_6s_ncr18650_2C.yaml\nrun: {duration_s: 5}\n");
  const RunResult r = runScenario(s);
  EXPECT_GE(test::eventTime(r, "relay_contact", "closed"), 0.0);
  EXPECT_TRUE(r.summary.relay_closed);
  EXPECT_EQ(relayLine(formatSummary(s, r)), "");
  EXPECT_TRUE(relayNeverClosed(s, r).empty());
  EXPECT_TRUE(judge(s, r).warnings.empty());
}

}  // namespace
}  // namespace packsim
