// `compare: {scenario: ...}`: the reference run is the plain run of that file, and the
// energy lost is (chemical − delivered) here minus there. System E at -15 °C against
// the same ride at 5 °C: the cold LTO cell's R0 (4x its 25 °C value) sags the pack
// further and turns more of the cells' energy into heat for the same ride.
#include <gtest/gtest.h>

#include "core/check/check.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

TEST(Comparison, ColdRideAgainstTheFiveDegreeRide) {
  const Scenario cold = loadScenarioFile(test::scenarioDir() + "/scooter_16s_lto_cold.yaml");
  const Scenario warm = loadScenarioFile(test::scenarioDir() + "/scooter_16s_lto.yaml");
  ASSERT_EQ(cold.compare_scenario, test::scenarioDir() + "/scooter_16s_lto.yaml");
  ASSERT_TRUE(warm.compare_scenario.empty());
  const RunResult c = runScenario(cold);
  const RunResult w = runScenario(warm);
  const Comparison& k = c.summary.compare;
  ASSERT_TRUE(k.present);
  EXPECT_EQ(k.name, "scooter_16s_lto");
  // The reference figures are the reference run's, bit for bit (same file, same seed).
  EXPECT_EQ(k.energy_delivered_Wh, w.summary.energy_delivered_Wh);
  EXPECT_EQ(k.min_cell_V, w.summary.min_cell_V);
  const double lossesWarm = w.quad[kQuadChemEnergy_J] / 3600.0 - w.summary.energy_delivered_Wh;
  const double lossesCold = c.quad[kQuadChemEnergy_J] / 3600.0 - c.summary.energy_delivered_Wh;
  EXPECT_EQ(k.losses_Wh, lossesWarm);
  EXPECT_EQ(k.lostWh(), lossesCold - lossesWarm);
  // A power load: the same energy out (to the solver's accuracy), more drawn in the cold.
  EXPECT_NEAR(c.summary.energy_delivered_Wh, w.summary.energy_delivered_Wh, 1e-3 * w.summary.energy_delivered_Wh);
  EXPECT_GT(k.lostWh(), 1.0);
  // The losses are the cells' heat (the RC charge left at the end is a few mWh).
  EXPECT_NEAR(lossesCold, c.summary.heat_Wh, 0.05);
  EXPECT_LT(c.summary.min_cell_V, w.summary.min_cell_V);
  const std::string text = formatSummary(cold, c);
  EXPECT_NE(text.find("compared with   scooter_16s_lto: "), std::string::npos) << text;
  EXPECT_NE(text.find("more energy lost"), std::string::npos) << text;
  EXPECT_TRUE(judge(cold, c).passed);

  // An expectation the comparison does not meet fails with its figures.
  Scenario strict = cold;
  strict.expect.energy_lost_vs_compare_Wh_above = 1000.0;
  const CheckOutcome o = judge(strict, c);
  EXPECT_FALSE(o.passed);
  ASSERT_EQ(o.failures.size(), 1u);
  EXPECT_NE(o.failures[0].find("energy lost against scooter_16s_lto"), std::string::npos) << o.failures[0];
}

TEST(Comparison, MissingReferenceFileIsALoadError) {
  try {
    test::scenarioFromYaml(test::simpleCellYaml() + test::kSimpleLoadYaml + "compare: {scenario: nope.yaml}\n");
    FAIL() << "accepted";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("compare.scenario: file not found"), std::string::npos) << e.what();
  }
  try {
    test::scenarioFromYaml(test::simpleCellYaml() + test::kSimpleLoadYaml +
                           "expect: {energy_lost_vs_compare_Wh_above: 1}\n");
    FAIL() << "accepted";
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("need a compare:"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace packsim
