// Reference system E on its charger: the team's 10 A charge takes about 2 h. From 5 % the
// CC phase alone needs 0.95 x 20 Ah / 10 A = 1.9 h; the firmware ends the charge when the
// first cell reads 2.75 V, so the fullest cell (the cells' capacities spread by 1.5 %)
// ends it a little earlier. The charge it put in is what the cells' SOC gained.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/scenario/load_scenario.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

TEST(ReferenceSystemE, TheTenAmpChargeTakesAboutTwoHoursAndStopsAtTheFullCellVoltage) {
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/scooter_16s_lto_charge.yaml");
  const RunResult r = runScenario(s);
  const Recording& rec = r.rec;
  const size_t n = 16, last = rec.samples() - 1;
  ASSERT_FALSE(r.summary.tripped) << r.summary.trip_reason;
  double first = -1.0, end = -1.0, maxCell_V = 0.0;
  for (size_t i = 0; i <= last; ++i) {
    if (rec.charger_current_A[i] > 0.01) {
      if (first < 0.0) first = rec.time_s[i];
      end = rec.time_s[i];
      EXPECT_LE(rec.charger_current_A[i], 10.0 + 1e-9);
    }
    EXPECT_LE(rec.pack_current_A[i], 1e-9) << "a charge only: nothing drawn from the pack";
    maxCell_V = std::max(maxCell_V, *std::max_element(&rec.cell_voltage_V[i * n], &rec.cell_voltage_V[i * n] + n));
  }
  const double hours = (end - first) / 3600.0;
  EXPECT_GT(hours, 1.7);
  EXPECT_LT(hours, 1.95);
  EXPECT_LT(maxCell_V, 2.80) << "the over-voltage rule never needed";
  // The charge in (coulombic efficiency 0.995) against the SOC the cells gained.
  double gained_Ah = 0.0;
  for (size_t c = 0; c < n; ++c) gained_Ah += rec.cell_soc[last * n + c] - rec.cell_soc[c];
  gained_Ah *= 20.0 / static_cast<double>(n);
  EXPECT_NEAR(gained_Ah, -0.995 * r.quad[kQuadCharge_As] / 3600.0, 0.02 * gained_Ah);  // capacities spread 1.5 %
  EXPECT_GT(gained_Ah, 18.0);
}

}  // namespace
}  // namespace packsim
