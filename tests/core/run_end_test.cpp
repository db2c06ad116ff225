// Why a run ended: the `run` event says it ("end: <reason>") and the summary's duration
// line repeats any reason but the scheduled end. Each test builds the case the old text
// got wrong or left out: a trip inside the last stop_after_trip_s (the run reached its
// scheduled end, but the event claimed it stopped 60 s after the trip), a trip early in
// the run, a charge that completed.
#include <gtest/gtest.h>

#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const Event* runEnd(const RunResult& r) {
  const Event* last = nullptr;
  for (const Event& e : r.events)
    if (e.kind == "run") last = &e;
  return last;
}

std::string durationLine(const std::string& summary) {
  const size_t at = summary.find("duration ");
  return at == std::string::npos ? "" : summary.substr(at, summary.find('\n', at) - at);
}

RunResult estopAt(double at_s, Scenario& s) {
  s = test::scenarioFromYaml(test::simpleCellYaml(4) + "load: {current_A: 1}\nrun: {duration_s: 200}\n" +
                             "faults:\n  - {kind: estop, switch: external, at_s: " + std::to_string(at_s) + "}\n");
  return runScenario(s);
}

TEST(RunEnd, ATripStopsTheRunItsStopAfterTripLaterAndTheDurationLineSaysSo) {
  Scenario s;
  const RunResult r = estopAt(20.0, s);
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_NEAR(r.summary.duration_s, r.summary.trip_time_s + 60.0, 0.02);
  const Event* end = runEnd(r);
  ASSERT_NE(end, nullptr);
  EXPECT_EQ(end->detail, "end: 60 s after the trip (run.stop_after_trip_s)");
  const std::string line = durationLine(formatSummary(s, r));
  EXPECT_TRUE(has(line, "; ended: 60 s after the trip (run.stop_after_trip_s), before run.duration_s = 200 s")) << line;
}

// The trip at 180 s of 200: the run goes to its scheduled end, 20 s after the trip. The
// event said "60 s after trip" here before.
TEST(RunEnd, ATripInTheLastStopAfterTripSecondsEndsAtTheScheduledEnd) {
  Scenario s;
  const RunResult r = estopAt(180.0, s);
  ASSERT_TRUE(r.summary.tripped);
  EXPECT_NEAR(r.summary.duration_s, 200.0, 1e-9);
  const Event* end = runEnd(r);
  ASSERT_NE(end, nullptr);
  EXPECT_EQ(end->detail, "end: the scenario's end time");
  const std::string line = durationLine(formatSummary(s, r));
  EXPECT_FALSE(has(line, "ended")) << line;
}

TEST(RunEnd, ACompletedChargeNamesItself) {
  const Scenario s = test::scenarioFromYaml(
      "name: full\npack: {series: 1, initial_soc: 0.97, cell: {preset: ncr18650_3p1Ah}}\n"
      "load: {charger: {current_A: 1.5, voltage_V: 4.2, end_current_A: 0.5}}\nrun: {duration_s: 7200}\n");
  const RunResult r = runScenario(s);
  ASSERT_GT(test::eventTime(r, "charger", "done"), 0.0);
  ASSERT_LT(r.summary.duration_s, 7200.0);
  const Event* end = runEnd(r);
  ASSERT_NE(end, nullptr);
  EXPECT_EQ(end->detail, "end: the charge was complete");
  const std::string line = durationLine(formatSummary(s, r));
  EXPECT_TRUE(has(line, "; ended: the charge was complete, before run.duration_s = 7200 s")) << line;
}

}  // namespace
}  // namespace packsim
