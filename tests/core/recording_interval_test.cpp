// output.interval_s: the recording keeps every n-th BMS tick, so its interval is a whole
// number of ticks. A stated interval that is not is refused with the nearest valid ones
// (it was rounded silently: 15 ms at a 10 ms tick recorded every 20 ms); the default is
// the whole number of ticks nearest 1 s (a 300 ms tick: 0.9 s; a 1.5 s tick: 1.5 s).
#include <gtest/gtest.h>

#include <cmath>

#include "core/scenario/overrides.hpp"
#include "core/scenario/provenance.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::string yamlWith(const std::string& extra) {
  return test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 12}\n" + extra;
}

Scenario load(const std::string& yaml) { return loadScenarioWithOverrides(yaml, {}, "test.yaml", test::scenarioDir()); }

TEST(RecordingInterval, AStatedIntervalOfPartTicksIsRefusedWithTheNearestWholeOnes) {
  const std::string y = yamlWith("output: {interval_s: 0.015}\n");
  const int line = static_cast<int>(std::count(y.begin(), y.end(), '\n'));  // the last line
  const std::string e = test::scenarioErrorOf([&] { load(y); });
  EXPECT_EQ(e.find("test.yaml:" + std::to_string(line) + ":22: output.interval_s: "), 0u) << e;
  EXPECT_NE(e.find("0.015 s is not a whole number of BMS ticks (bms.tick_ms 10)"), std::string::npos) << e;
  EXPECT_NE(e.find("; 0.01 or 0.02"), std::string::npos) << e;
  const std::string shorter = test::scenarioErrorOf([&] { load(yamlWith("output: {interval_s: 0.004}\n")); });
  EXPECT_NE(shorter.find("at least 0.01"), std::string::npos) << shorter;
}

TEST(RecordingInterval, WholeTicksAreTakenAsStated) {
  for (const char* v : {"0.01", "0.1", "0.3", "1", "2.5"}) {
    const Scenario s = load(yamlWith(std::string("output: {interval_s: ") + v + "}\n"));
    EXPECT_EQ(s.output.interval_s, std::stod(v)) << v;
  }
}

// The default at ticks that do not divide 1 s, against the recording's own time axis.
TEST(RecordingInterval, TheDefaultIsTheWholeNumberOfTicksNearestOneSecond) {
  for (const auto& [tick_ms, expect_s] : {std::pair{300, 0.9}, std::pair{1500, 1.5}, std::pair{10, 1.0}}) {
    SCOPED_TRACE(tick_ms);
    const Scenario s = load(yamlWith("bms: {tick_ms: " + std::to_string(tick_ms) + "}\n"));
    EXPECT_NEAR(s.output.interval_s, expect_s, 1e-12);
    if (tick_ms != 10) {
      ASSERT_TRUE(s.provenance);
      EXPECT_EQ(s.provenance->originOf("output.interval_s"), "default (the whole number of BMS ticks nearest 1 s)");
    }
    const RunResult r = runScenario(s);
    ASSERT_GE(r.rec.samples(), 3u);
    for (size_t i = 1; i + 1 < r.rec.samples(); ++i)  // the last sample is the run's end
      EXPECT_NEAR(r.rec.time_s[i] - r.rec.time_s[i - 1], expect_s, 1e-9) << i;
  }
}

}  // namespace
}  // namespace packsim
