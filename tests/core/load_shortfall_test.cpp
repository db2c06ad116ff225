// A power load past the pack's maximum power point is held there (core/sim/plant.cpp);
// the run says so: a `load_limited` event per episode, a line under `load`, a `check`
// warning. Judged on the recorded truth: the episode is the ticks where V*I fell short
// of the asked power, the most given is the recorded maximum of V*I there, and the
// energy short is the recorded shortfall summed over them.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/check/check.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::vector<const Event*> limited(const RunResult& r) { return test::eventsOf(r, "load_limited"); }

// 4s1p of the simple 2 Ah cell (E ~ 16.2 V, R0 4 x 20 mOhm): at most ~820 W. 2000 W
// from 2 s to 4 s is past it; 50 W around it is not.
std::string powerYaml(double peak_W) {
  std::string cells = test::simpleCellYaml(4);  // a current sensor that reads the ~100 A at the maximum power point
  const std::string sensor = "shunt_ohm: 0.001, amp_gain: 20";
  cells.replace(cells.find(sensor), sensor.size(), "shunt_ohm: 0.0001, amp_gain: 10");
  return cells +
         "load:\n  segments:\n    - {duration_s: 2, power_W: 50}\n    - {duration_s: 2, power_W: " +
         std::to_string(peak_W) + "}\n    - {duration_s: 2, power_W: 50}\n" +
         "run: {duration_s: 6}\noutput: {interval_s: 0.01}\n"
         "bms: {protections: {overcurrent_discharge: {enabled: false}, cell_undervoltage: {threshold_V: 0.5}}}\n";
}

TEST(LoadShortfall, APowerLoadPastTheMaximumPowerPointIsAnEpisodeWithItsFigures) {
  const Scenario s = test::scenarioFromYaml(powerYaml(2000.0));
  const RunResult r = runScenario(s);
  const auto events = limited(r);
  ASSERT_EQ(events.size(), 1u);
  const Event& e = *events[0];
  EXPECT_TRUE(has(e.detail, "2.00-4.00 s: the pack gave less power than the load asked")) << e.detail;
  EXPECT_TRUE(has(e.detail, "while up to 2000 W was asked")) << e.detail;
  // The record: every sample in [2, 4) short of 2000 W, none short of 50 W outside; the most given and
  // the energy short from the recorded V*I.
  const Recording& rec = r.rec;
  double most = 0.0, short_J = 0.0;
  for (size_t i = 0; i < rec.samples(); ++i) {
    const double t = rec.time_s[i], p = rec.pack_voltage_V[i] * rec.pack_current_A[i];
    const bool inside = t >= 2.0 - 1e-9 && t < 4.0 - 1e-9;
    if (t < 0.05 || t > 6.0 - 1e-9) continue;  // the relay closes after the first ticks; the profile ends at 6 s
    const double asked = inside ? 2000.0 : 50.0;
    EXPECT_EQ(inside, p < asked * (1.0 - 1e-6)) << "t = " << t << " s, " << p << " W";
    if (inside) most = std::max(most, p), short_J += (2000.0 - p) * 0.01;
  }
  ASSERT_GT(most, 100.0);
  char given[64];
  std::snprintf(given, sizeof given, "at most %.0f W", most);
  EXPECT_TRUE(has(e.detail, given)) << e.detail;
  char wh[64];
  std::snprintf(wh, sizeof wh, "about %.2f Wh short", short_J / 3600.0);
  EXPECT_TRUE(has(e.detail, wh)) << e.detail;
  EXPECT_TRUE(has(formatSummary(s, r), "load            " + e.detail)) << formatSummary(s, r);
  const CheckOutcome o = judge(s, r);
  EXPECT_NE(std::find(o.warnings.begin(), o.warnings.end(), "load not met: " + e.detail), o.warnings.end());
}

TEST(LoadShortfall, APowerLoadThePackGivesAndACurrentLoadHaveNone) {
  EXPECT_TRUE(limited(runScenario(test::scenarioFromYaml(powerYaml(100.0)))).empty());
  EXPECT_TRUE(limited(runScenario(test::scenarioFromYaml(test::simpleCellYaml(4) + test::kSimpleLoadYaml))).empty());
}

}  // namespace
}  // namespace packsim
