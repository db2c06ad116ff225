// Energy back into the pack (regeneration, a charger) beside the net energy out: a run
// that both discharges and charges says how much went each way, and the two add up to
// the net the quadrature gives.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

using namespace packsim;

namespace {
// A 10 Ah cell with OCV = 3.65 + 0.1·SOC, a constant 20 mOhm and no RC pair: at a
// constant current I over T its terminals give I·(3.65 + 0.1·SOC_mean - 0.02·I)·T, SOC
// moving linearly (coulombic efficiency 1).
std::string flatCell(const std::string& load, double duration_s = 0.0) {
  return "name: regen\npack: {series: 1, initial_soc: 0.5, cell: {capacity_Ah: 10, ocv_V: {poly: [0.1, 3.65]}, "
         "r0_ohm: 0.02, coulombic_efficiency: 1.0, heat_capacity_J_per_K: 200, g_ambient_W_per_K: 0.5}}\n"
         "hardware: {thermistors: {at_groups: [1]}}\nrun: {solver: fast" +
         (duration_s > 0.0 ? ", duration_s: " + std::to_string(duration_s) : std::string()) + "}\n" + load;
}
// A segment of I amperes for T seconds from SOC `soc` (moved on): its energy out [J].
double segment_J(double i, double t_s, double& soc) {
  const double end = soc - i * t_s / 36000.0;
  const double e = i * (3.65 + 0.1 * 0.5 * (soc + end) - 0.02 * i) * t_s;
  soc = end;
  return e;
}
}  // namespace

TEST(EnergyIn, ARegenerationSegmentIsBackInAndOutLessInIsTheNet) {
  // 10 A out to 100 s, 5 A in for 50 s, 10 A out for 50 s more; the relay closes a tick
  // or two after t = 0, so the first segment's time out is measured from its contact.
  const Scenario s = test::scenarioFromYaml(flatCell(
      "load: {segments: [{duration_s: 100, current_A: 10}, {duration_s: 50, current_A: -5},"
      " {duration_s: 50, current_A: 10}]}\n"));
  const RunResult r = runScenario(s);
  const double closed_s = test::eventTime(r, "relay_contact", "closed");
  ASSERT_GE(closed_s, 0.0);
  double soc = 0.5;
  const double out1_J = segment_J(10.0, 100.0 - closed_s, soc);
  const double in_J = -segment_J(-5.0, 50.0, soc);  // about 5 A · 3.8 V · 50 s = 950 J
  const double out_J = out1_J + segment_J(10.0, 50.0, soc);
  EXPECT_NEAR(r.summary.energy_in_Wh * 3600.0, in_J, 1e-6 * in_J);
  EXPECT_NEAR(r.summary.energy_delivered_Wh * 3600.0, out_J - in_J, 1e-6 * out_J);
  // The line: net, then out and back in, which add up as printed.
  const std::string text = formatSummary(s, r);
  char want[160];
  std::snprintf(want, sizeof want, "energy out      %.2f Wh net  (%.2f Wh out, %.2f Wh back in; ",
                r.summary.energy_delivered_Wh, r.summary.energy_delivered_Wh + r.summary.energy_in_Wh,
                r.summary.energy_in_Wh);
  EXPECT_NE(text.find(want), std::string::npos) << text;
  EXPECT_NE(text.find("0.26 Wh back in"), std::string::npos) << text;  // ~950 J
}

TEST(EnergyIn, ADischargeAloneHasNothingBackInAndNoNetWording) {
  const Scenario s = test::scenarioFromYaml(flatCell("load: {current_A: 10}\n", 60.0));
  const RunResult r = runScenario(s);
  EXPECT_EQ(r.summary.energy_in_Wh, 0.0);
  const std::string text = formatSummary(s, r);
  EXPECT_EQ(text.find(" Wh net"), std::string::npos) << text;
  EXPECT_NE(text.find("energy out      "), std::string::npos) << text;
}

TEST(EnergyIn, AChargeIsAllBackIn) {
  // A CC-CV charger: the net out is minus what went in.
  const Scenario s = test::scenarioFromYaml(
      flatCell("load: {charger: {current_A: 5, voltage_V: 4.2}}\n", 120.0));
  const RunResult r = runScenario(s);
  ASSERT_GT(r.summary.energy_in_Wh, 0.0);
  EXPECT_NEAR(r.summary.energy_delivered_Wh, -r.summary.energy_in_Wh, 1e-12);
}
