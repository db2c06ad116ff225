// One-state hysteresis against its closed form and the energy balance:
//
//   constant discharge I from h = 0:  h(t) = -M·(1 - exp(-γ·I·t/3600))
//   V(t) = OCV(soc) + h - M0 - I·R0 - v1(t)
//   ∫OCV·I dt = load + heat (Joule + hysteresis loss -I·(h - M0·sgn I)) + ½·C·v1²
#include <gtest/gtest.h>

#include <cmath>

#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

constexpr double kQ = 2.0, kR0 = 0.02, kR1 = 0.01, kC1 = 1000.0, kSoc0 = 0.8;
constexpr double kM = 0.03, kGamma = 20.0, kM0 = 0.005;

double ocv(double soc) { return 3.4 + 0.8 * soc; }

std::string withHysteresis(int series) {
  std::string y = test::simpleCellYaml(series);
  const std::string r0 = "    r0_ohm: 0.02\n";
  y.replace(y.find(r0), r0.size(), r0 + "    hysteresis: {max_V: 0.03, rate_per_Ah: 20, instantaneous_V: 0.005}\n");
  return y;
}

TEST(CellHysteresis, ConstantDischargeFollowsClosedForm) {
  constexpr double kI = 3.0;
  for (const char* solver : {"cvode", "fast"}) {
    const std::string run = std::string(solver) == "fast" ? "solver: fast" : "rtol: 1e-9";
    const Scenario s = test::scenarioFromYaml(withHysteresis(1) + "load: {current_A: 3}\nrun: {duration_s: 300, " + run + "}\n");
    ASSERT_TRUE(s.pack.cell.has_hysteresis);
    const RunResult r = runScenario(s);
    const double tc = test::eventTime(r, "relay", "close");
    ASSERT_GE(tc, 0.0);
    ASSERT_FALSE(r.summary.tripped);
    for (double t : {5.0, 30.0, 120.0, 299.0}) {
      const size_t k = test::sampleAt(r.rec, t);
      const double tau = t - tc;
      const double h = -kM * (1.0 - std::exp(-kGamma * kI * tau / 3600.0));
      const double v = ocv(kSoc0 - kI * tau / (3600.0 * kQ)) + h - kM0 - kI * kR0 -
                       kI * kR1 * (1.0 - std::exp(-tau / (kR1 * kC1)));
      EXPECT_NEAR(r.rec.cell_voltage_V[k], v, 2e-6 * v) << solver << " t=" << t;
    }
  }
}

// Charge and discharge: the hysteresis voltage is a loss that shows up as heat, and the
// balance closes with it; over the run the loss is positive.
TEST(CellHysteresis, EnergyBalanceIncludesTheHysteresisVoltage) {
  const std::string load = "load:\n  segments:\n    - {duration_s: 40, current_A: 6}\n"
                           "    - {duration_s: 40, current_A: -4}\n    - {duration_s: 20, current_A: 0}\n"
                           "  laps: 8\nrun: {rtol: 1e-8}\n"
                           // 4 A into a 2 Ah cell is 2C: above the 1C charge limit a cell without
                           // a max_charge_C gets (docs/scenario.md); this test is about energy.
                           "bms: {protections: {overcurrent_charge: {threshold_A: 5}}}\n";
  // (8 laps of +240 As / -160 As from SOC 0.8 of 2 Ah: SOC stays within 0.71..0.8.)
  const RunResult with = runScenario(test::scenarioFromYaml(withHysteresis(2) + load));
  const RunResult without = runScenario(test::scenarioFromYaml(test::simpleCellYaml(2) + load));
  // The currents are the same in both runs (current loads, no temperature-dependent
  // element), so the RC voltages are too: at rest v1 = OCV - V of the run without h.
  const size_t last = without.rec.samples() - 1;
  ASSERT_EQ(without.rec.pack_current_A[last], 0.0);
  double stored = 0.0;
  for (int c = 0; c < without.rec.cells; ++c) {
    const size_t k = last * static_cast<size_t>(without.rec.cells) + static_cast<size_t>(c);
    const double v1 = ocv(without.rec.cell_soc[k]) - without.rec.cell_voltage_V[k];
    stored += 0.5 * kC1 * v1 * v1;
  }
  for (const RunResult* r : {&with, &without}) {
    ASSERT_FALSE(r->summary.tripped);
    const double chem = r->quad[kQuadChemEnergy_J];
    EXPECT_NEAR(chem, r->quad[kQuadLoadEnergy_J] + r->quad[kQuadHeat_J] + stored, 1e-5 * chem);
  }
  // The same charge passes in both runs (current loads): the hysteresis loss is the
  // difference in energy delivered plus the difference in stored energy; it is positive
  // and of the size M·(charge passed): between (M)·|Q| / 4 and (M + M0)·|Q|.
  const double lossExtra = with.quad[kQuadHeat_J] - without.quad[kQuadHeat_J];
  const double charge_As = 8.0 * (6.0 * 40.0 + 4.0 * 40.0) * 2.0;  // both cells
  EXPECT_GT(lossExtra, 0.25 * kM * charge_As);
  EXPECT_LT(lossExtra, (kM + kM0) * charge_As);
  EXPECT_NEAR(without.quad[kQuadLoadEnergy_J] - with.quad[kQuadLoadEnergy_J], lossExtra, 0.02 * lossExtra);
}

TEST(CellHysteresis, BadBlockIsRefused) {
  std::string y = test::simpleCellYaml() + test::kSimpleLoadYaml;
  y.replace(y.find("    r0_ohm: 0.02\n"), 17, "    r0_ohm: 0.02\n    hysteresis: {max_V: {poly: [0.04, -0.01]}, rate_per_Ah: 20}\n");
  try {
    test::scenarioFromYaml(y);
    FAIL() << "accepted";
  } catch (const ScenarioError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test.yaml:11:"), std::string::npos) << m;
    EXPECT_NE(m.find("hysteresis.max_V: must be >= 0"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace packsim
