// State estimation judged against the truth (docs/state-estimation.md), on bundled
// races: the EKF converges from a wrong initial SOC; coulomb counting's error grows
// with a current-sense offset exactly as the firmware's integral of it says; the
// `expect:` bounds fail when they should; bad estimator keys are clear errors.
#include <gtest/gtest.h>

#include <cmath>

#include "core/check/check.hpp"
#include "core/scenario/overrides.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

std::string eco() { return test::scenarioDir() + "/eco_marathon_12s.yaml"; }

// System A race, EKF told the pack is at 50 % (with its default, overconfident 5 %
// initial sigma) while it is at 95 %: within 120 s of racing the error is below 2 % and
// stays there for the rest of the race (measured: 81 s).
TEST(SocEstimation, EkfConvergesFromAWrongInitialSocOnTheEcoMarathonRace) {
  const Scenario s = loadScenarioFileWithOverrides(
      eco(), {{"bms.soc.estimator", "ekf"}, {"bms.soc.ekf.initial_soc", "0.5"}});
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  ASSERT_GT(rec.samples(), 2000u);
  EXPECT_GT(std::fabs(rec.soc_ekf[0] - rec.soc_truth_mean[0]), 0.4);  // started wrong
  double lastBad_s = 0.0;
  for (size_t i = 0; i < rec.samples(); ++i)
    if (std::fabs(rec.soc_ekf[i] - rec.soc_truth_mean[i]) >= 0.02) lastBad_s = rec.time_s[i];
  EXPECT_LE(lastBad_s, 120.0);
  EXPECT_GT(r.summary.soc_error_ekf.max, 0.3);  // the judged max includes the start
  EXPECT_LT(std::fabs(r.summary.soc_error_ekf.end), 0.02);
}

// A current-sense offset a + b·(t - t0) from t0 on: the coulomb counter's SOC moves
// away from the healthy run's by the firmware's rectangle-rule sum of the offset over
// its ticks divided by its capacity, to float resolution (same seed: same noise).
TEST(SocEstimation, CoulombErrorGrowsWithACurrentOffsetExactlyAsItsIntegral) {
  const Overrides base = {{"load.laps", "3"}};
  Overrides drift = base;
  drift.push_back({"faults", "[{kind: current_sensor_drift, offset_A: 0.3, drift_A_per_h: 2.0, at_s: 100}]"});
  const Scenario healthy = loadScenarioFileWithOverrides(eco(), base);
  const Scenario faulty = loadScenarioFileWithOverrides(eco(), drift);
  const RunResult a = runScenario(healthy), b = runScenario(faulty);
  ASSERT_EQ(a.rec.samples(), b.rec.samples());
  const double tick_s = healthy.bms.tick_s, capacity_As = 5.0 * 3600.0;
  const double a_A = 0.3, b_A_per_s = 2.0 / 3600.0, t0 = 100.0;
  double worst = 0.0, largest = 0.0;
  for (size_t i = 0; i < a.rec.samples(); ++i) {
    const double t = a.rec.time_s[i];
    double counted_As = 0.0;  // Σ offset(t_j)·dt over the ticks t0 <= t_j <= t
    for (long k = std::lround(t0 / tick_s); k <= std::lround(t / tick_s); ++k)
      counted_As += (a_A + b_A_per_s * (static_cast<double>(k) * tick_s - t0)) * tick_s;
    const double expected = -counted_As / capacity_As;
    const double measured = b.rec.soc_coulomb[i] - a.rec.soc_coulomb[i];
    worst = std::max(worst, std::fabs(measured - expected));
    largest = std::max(largest, std::fabs(expected));
  }
  EXPECT_GT(largest, 0.015);  // the offset matters: 1.9 % by the end of 3 laps
  EXPECT_LT(worst, 2e-5);     // and the error is exactly its integral
  // The healthy truth moved the same in both runs (the offset reaches only the sensor).
  EXPECT_EQ(a.rec.soc_truth_mean.back(), b.rec.soc_truth_mean.back());
}

// The expect bounds: a wrong firmware capacity makes coulomb counting miss a tight
// bound, and check says which estimator and by how much.
TEST(SocEstimation, CheckFailsAnUnmetSocErrorBound) {
  const Scenario s = loadScenarioFileWithOverrides(
      eco(), {{"load.laps", "3"}, {"bms.soc.cell_capacity_Ah", "4.0"},
              {"expect", "{soc_error_max_below: {coulomb: 0.01, ekf: 0.5}}"}});
  const CheckOutcome c = judge(s, runScenario(s));
  ASSERT_EQ(c.failures.size(), 1u);
  EXPECT_NE(c.failures[0].find("coulomb SOC error max"), std::string::npos) << c.failures[0];
}

// The EKF runs per series group: a 2 % gain error on cell 6's input (about 80 mV)
// misleads group 6 alone, by at least that voltage over the OCV table's steepest slope
// (1.2 V per unit SOC between 90 and 100 %): more than 6 %.
TEST(SocEstimation, EkfGroupErrorPointsAtTheMisreadGroup) {
  const Scenario s = loadScenarioFileWithOverrides(
      eco(), {{"load.laps", "3"}, {"faults", "[{kind: channel_gain, cell: 6, gain_error: 0.02, at_s: 0}]"}});
  const RunResult r = runScenario(s);
  EXPECT_EQ(r.summary.soc_error_ekf_group, 6);
  EXPECT_GT(r.summary.soc_error_ekf_group_max, 0.06);
  EXPECT_LT(r.summary.soc_error_ekf.max, r.summary.soc_error_ekf_group_max / 6);  // the pack mean carries 1/12
}

TEST(SocEstimation, BadEstimatorKeysAreClearErrors) {
  auto message = [](const Overrides& o) {
    try {
      loadScenarioFileWithOverrides(eco(), o);
    } catch (const ScenarioError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message({{"bms.soc.estimator", "ekff"}}).find("did you mean 'ekf'"), std::string::npos);
  EXPECT_NE(message({{"bms.soc.ocv_V", "[3.0, 3.9, 3.8]"}}).find("rise strictly"), std::string::npos);
  EXPECT_NE(message({{"bms.soc.display_bars_V", "[3.3, 3.4]"}}).find("at least 7 values"), std::string::npos);
  EXPECT_NE(message({{"bms.soc.cell_r0_ohm", "[0.01, 0.02]"}}).find("one per OCV table point (11)"), std::string::npos);
  EXPECT_NO_THROW(loadScenarioFileWithOverrides(eco(), {{"bms.soc.cell_r0_ohm", "0.008"}}));
  EXPECT_NE(message({{"expect", "{soc_error_max_below: {ekf: 2}}"}}).find("expect.soc_error_max_below.ekf"),
            std::string::npos);
  EXPECT_NE(message({{"expect", "{soc_error_max_below: {ekff: 0.1}}"}}).find("did you mean"), std::string::npos);
}

}  // namespace
}  // namespace packsim
