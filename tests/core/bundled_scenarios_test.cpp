// Every bundled scenario passes its expect block, and the reference packs show the
// figures of docs/reference-systems.md.
#include <gtest/gtest.h>

#include <cctype>
#include <string>

#include <filesystem>

#include "core/check/check.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

// One test per bundled scenario, as `packsim check scenarios` collects them (a loop over
// all of them ran 60 s on two cores).
class BundledScenario : public ::testing::TestWithParam<std::string> {};

TEST_P(BundledScenario, PassesItsExpectBlock) {
#ifndef PACKSIM_TARGET_ELF_DIR
  if (GetParam().find("/firmware/target/") != std::string::npos)
    GTEST_SKIP() << "arm-none-eabi-gcc was not found when packsim was configured: no target ELF for " << GetParam();
#endif
  const CheckOutcome c = checkScenarioFile(GetParam());
  EXPECT_TRUE(c.passed) << GetParam() << ": "
                        << (c.error ? c.error_message : c.failures.empty() ? "" : c.failures[0]);
}

std::string scenarioTestName(const ::testing::TestParamInfo<std::string>& info) {
  std::string n = info.param.substr(std::string(PACKSIM_SCENARIO_DIR).size() + 1);
  n = n.substr(0, n.size() - 5);  // without .yaml
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n;
}

INSTANTIATE_TEST_SUITE_P(Every, BundledScenario, ::testing::ValuesIn(collectScenarioFiles({PACKSIM_SCENARIO_DIR})),
                         scenarioTestName);

TEST(BundledScenarios, AtLeastTheSixReferenceScenariosAreCollected) {
  EXPECT_GE(collectScenarioFiles({test::scenarioDir()}).size(), 6u);
}

// System A default: a 12s LiPo pack (≈44 V nominal) stays under the 60 V vehicle cap.
TEST(BundledScenarios, EcoMarathonStaysUnderTheVehicleVoltageCap) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/eco_marathon_12s.yaml");
  EXPECT_EQ(s.pack.series, 12);
  const RunResult r = runScenario(s);
  double vmax = 0.0;
  for (double v : r.rec.pack_voltage_V) vmax = std::max(vmax, v);
  EXPECT_LT(vmax, 60.0);
  EXPECT_GT(vmax, 40.0);
  EXPECT_GT(r.summary.max_temp_C, s.ambient_C.at(0.0));
}

// System B: the race ends on the weakest module with energy left in the others --
// up to 5 % of the pack energy unusable.
TEST(BundledScenarios, SolarCarStrandsUpToFivePercent) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/solar_car_28s15p.yaml");
  EXPECT_EQ(s.pack.series * s.pack.parallel, 420);
  const RunResult r = runScenario(s);
  ASSERT_TRUE(r.summary.limit_reached);
  const double frac = r.summary.energy_stranded_Wh / r.summary.energy_start_Wh;
  EXPECT_GT(frac, 0.005);
  EXPECT_LE(frac, 0.05);
  double vmax = 0.0;
  for (double v : r.rec.pack_voltage_V) vmax = std::max(vmax, v);
  EXPECT_LT(vmax, 117.6);  // 28 x 4.2 V
}

}  // namespace
}  // namespace packsim
