// Conservation over a full race profile, against independent figures.
#include <gtest/gtest.h>

#include <cmath>

#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

Scenario race() {
  Scenario s = test::scenarioFromYaml(test::simpleCellYaml(4) +
                                      "load:\n"
                                      "  segments:\n"
                                      "    - {duration_s: 30, current_A: 8}\n"
                                      "    - {duration_s: 45, current_A: 3}\n"
                                      "    - {duration_s: 20, current_A: 0}\n"
                                      "    - {duration_s: 15, current_A: 6.5}\n"
                                      "  laps: 12\n"
                                      "run: {rtol: 1e-8}\n");
  return s;
}

// ∫ I dt (from the profile, exactly, from the moment the relay closed) equals
// capacity × ΔSOC of every cell.
TEST(Conservation, ChargeEqualsCapacityTimesDeltaSoc) {
  const Scenario s = race();
  const RunResult r = runScenario(s);
  ASSERT_FALSE(r.summary.tripped);
  const double tc = test::eventTime(r, "relay", "close");
  const double tEnd = r.rec.time_s.back();
  const double charge_As = s.load.chargeUntil_As(tEnd) - s.load.chargeUntil_As(tc);
  ASSERT_GT(charge_As, 3000.0);
  const size_t last = r.rec.samples() - 1;
  for (int c = 0; c < r.rec.cells; ++c) {
    const double dsoc = 0.8 - r.rec.cell_soc[last * static_cast<size_t>(r.rec.cells) + static_cast<size_t>(c)];
    EXPECT_NEAR(2.0 * 3600.0 * dsoc, charge_As, 1e-6 * charge_As) << "cell " << c + 1;
  }
  EXPECT_NEAR(r.quad[kQuadCharge_As], charge_As, 1e-6 * charge_As);
}

// Energy drawn from the cells' OCV = energy to the load + Joule heat + energy still
// stored in the RC capacitors (½·C·v² per cell).
TEST(Conservation, EnergyBalances) {
  const Scenario s = race();
  const RunResult r = runScenario(s);
  const size_t last = r.rec.samples() - 1;
  const double i = r.rec.pack_current_A[last];
  ASSERT_EQ(i, 0.0);  // profile ends at rest: v_rc = OCV - V (no R0 drop)
  double stored = 0.0;
  for (int c = 0; c < r.rec.cells; ++c) {
    const size_t k = last * static_cast<size_t>(r.rec.cells) + static_cast<size_t>(c);
    const double v1 = 3.4 + 0.8 * r.rec.cell_soc[k] - r.rec.cell_voltage_V[k];
    stored += 0.5 * 1000.0 * v1 * v1;
  }
  const double chem = r.quad[kQuadChemEnergy_J];
  EXPECT_NEAR(chem, r.quad[kQuadLoadEnergy_J] + r.quad[kQuadHeat_J] + stored, 1e-5 * chem);
}

}  // namespace
}  // namespace packsim
