// Every bundled scenario loads and runs, and the default race gives a sane summary.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

TEST(BundledScenarios, AllLoadAndRun) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(test::scenarioDir())) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().string());
    const Scenario s = loadScenarioFile(e.path().string());
    const RunResult r = runScenario(s);
    EXPECT_GT(r.rec.samples(), 1u);
    EXPECT_GT(r.summary.duration_s, 0.0);
    ++n;
  }
  EXPECT_GE(n, 1);
}

// System A default: a 12s LiPo pack (≈44 V nominal) stays under the 60 V vehicle cap
// and the BMS isolates it automatically at the end of charge.
TEST(BundledScenarios, EcoMarathonDefaultRace) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/eco_marathon_12s.yaml");
  EXPECT_EQ(s.pack.series, 12);
  const RunResult r = runScenario(s);
  double vmax = 0.0;
  for (double v : r.rec.pack_voltage_V) vmax = std::max(vmax, v);
  EXPECT_LT(vmax, 60.0);
  EXPECT_GT(vmax, 40.0);
  EXPECT_GT(r.summary.energy_delivered_Wh, 50.0);
  EXPECT_GT(r.summary.max_temp_C, s.ambient_C.at(0.0));
}

}  // namespace
}  // namespace packsim
