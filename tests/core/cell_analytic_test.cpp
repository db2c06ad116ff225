// A single cell at constant current with constant parameters against the closed form:
//
//   soc(t)  = soc0 - I·t / (3600·Q)
//   v1(t)   = I·R1·(1 - exp(-t / (R1·C1)))
//   V(t)    = OCV(soc(t)) - I·R0 - v1(t)          (OCV linear in soc)
//   T(∞)    = T_amb + I²·(R0 + R1) / G_amb
#include <gtest/gtest.h>

#include <cmath>

#include "core/sim/cvode_integrator.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "plant_only.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

constexpr double kI = 3.0, kQ = 2.0, kR0 = 0.02, kR1 = 0.01, kC1 = 1000.0, kSoc0 = 0.8, kG = 0.1;

double ocv(double soc) { return 3.4 + 0.8 * soc; }

TEST(CellAnalytic, ConstantCurrentMatchesClosedForm) {
  Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 3}\nrun: {duration_s: 3600}\n");
  const Plant plant(s);
  test::PlantOnly ode(plant, kI);
  CvodeIntegrator integ(ode, 1e-10);
  std::vector<double> x(plant.stateSize());
  plant.initialState(x.data());
  integ.reset(0.0, x.data());
  for (double t : {1.0, 5.0, 10.0, 60.0, 600.0, 1800.0}) {
    integ.advance(t, 1e9);
    const double* y = integ.state();
    const double soc = kSoc0 - kI * t / (3600.0 * kQ);
    const double v1 = kI * kR1 * (1.0 - std::exp(-t / (kR1 * kC1)));
    const double v = ocv(soc) - kI * kR0 - v1;
    PlantSignals sig = plant.makeSignals();
    plant.evaluate(t, y, ode.in, sig);
    EXPECT_NEAR(y[0], soc, 1e-6 * soc) << "t=" << t;
    EXPECT_NEAR(y[1], v1, 1e-6 * v1) << "t=" << t;
    EXPECT_NEAR(sig.cell_voltage_V[0], v, 1e-6 * v) << "t=" << t;
  }
}

TEST(CellAnalytic, TemperatureApproachesSteadyState) {
  Scenario s = test::scenarioFromYaml(test::simpleCellYaml() + "load: {current_A: 3}\nrun: {duration_s: 3600}\n");
  const Plant plant(s);
  test::PlantOnly ode(plant, kI);
  CvodeIntegrator integ(ode, 1e-10);
  std::vector<double> x(plant.stateSize());
  plant.initialState(x.data());
  integ.reset(0.0, x.data());
  // Thermal time constant C/G = 400 s; after 12 of them the transient is e^-12 ≈ 6e-6.
  integ.advance(4800.0, 1e9);
  const double tss = 25.0 + kI * kI * (kR0 + kR1) / kG;
  EXPECT_NEAR(integ.state()[plant.tempIndex(0)], tss, 1e-4);
  EXPECT_GT(integ.state()[plant.tempIndex(0)], 25.0 + 0.999 * (tss - 25.0));
}

// The same physics through the whole loop (sensors, BMS, relay): current flows once
// the BMS has closed the relay, and the terminal voltage follows the closed form
// from that moment.
TEST(CellAnalytic, FullLoopFollowsClosedFormAfterRelayCloses) {
  Scenario s = test::scenarioFromYaml(test::simpleCellYaml() +
                                      "load: {current_A: 3}\nrun: {duration_s: 600, rtol: 1e-9}\n"
                                      "output: {interval_s: 0.01}\n");
  const RunResult r = runScenario(s);
  const double tc = test::eventTime(r, "relay", "close");
  ASSERT_GE(tc, 0.0);
  ASSERT_FALSE(r.summary.tripped);
  for (double t : {10.0, 100.0, 599.0}) {
    const size_t i = test::sampleAt(r.rec, t);
    const double tau = t - tc;
    const double v = ocv(kSoc0 - kI * tau / (3600.0 * kQ)) - kI * kR0 - kI * kR1 * (1.0 - std::exp(-tau / (kR1 * kC1)));
    EXPECT_NEAR(r.rec.cell_voltage_V[i], v, 1e-6 * v) << "t=" << t;
  }
}

}  // namespace
}  // namespace packsim

namespace packsim {
namespace {

// Beyond full and empty the OCV continues along the slope of its last 1 % of SOC (an
// overcharged cell's voltage keeps rising, so an over-voltage check can see it): on the
// LiPo preset's table, whose last segment runs 4.08 -> 4.19 V over 0.9 -> 1.0, that is
// 1.1 V per unit of SOC above full and 6.8 V per unit (3.27 -> 3.61 V over 0 -> 0.05)
// below empty; inside [0, 1] the table itself.
TEST(CellAnalytic, OcvContinuesAlongItsEndSlopesBeyondFullAndEmpty) {
  const Scenario s = test::scenarioFromYaml(
      "name: ocv_ends\npack: {series: 1, cell: {preset: lipo_5Ah}}\nload: {current_A: 0}\nrun: {duration_s: 1}\n");
  const CellParams& p = s.pack.cell;
  EXPECT_NEAR(ecm::ocv(p, 1.0, 25.0), 4.19, 1e-12);
  EXPECT_NEAR(ecm::ocv(p, 1.05, 25.0), 4.19 + 0.05 * 1.1, 1e-9);
  EXPECT_NEAR(ecm::ocv(p, 1.20, 25.0), 4.19 + 0.20 * 1.1, 1e-9);
  EXPECT_NEAR(ecm::ocv(p, -0.02, 25.0), 3.27 - 0.02 * 6.8, 1e-9);
  EXPECT_NEAR(ecm::ocv(p, 0.95, 25.0), 4.135, 1e-12);
}

// A balancing switch that conducts a share d of the time (the monitor IC opens it for
// its conversions) carries d·V/R on average: over an hour at rest, with a 47 Ω resistor,
// the charge the cell lost is d·V̄·t/R, V̄ the mean of its terminal voltage at the start
// and the end (the OCV is linear in SOC, so V falls almost linearly) -- to 0.1 %, for the
// switch always on and for a BQ76952 inner cell's 6/7.
TEST(CellAnalytic, BalancingAtADutyRemovesThatShareOfTheCharge) {
  std::string yaml = test::simpleCellYaml();
  yaml.replace(yaml.find("hardware:\n"), 10, "hardware:\n  balancing: {resistor_ohm: 47}\n");
  const Scenario s = test::scenarioFromYaml(yaml + "load: {current_A: 0}\nrun: {duration_s: 3600}\n");
  const Plant plant(s);
  for (double duty : {1.0, 6.0 / 7.0}) {
    test::PlantOnly ode(plant, 0.0);
    ode.in.balancing = {1};
    ode.in.balance_duty = {duty};
    CvodeIntegrator integ(ode, 1e-10);
    std::vector<double> x(plant.stateSize());
    plant.initialState(x.data());
    integ.reset(0.0, x.data());
    PlantSignals sig = plant.makeSignals();
    plant.evaluate(0.0, x.data(), ode.in, sig);
    const double v0 = sig.cell_voltage_V[0];
    integ.advance(3600.0, 1e9);
    plant.evaluate(3600.0, integ.state(), ode.in, sig);
    const double v1 = sig.cell_voltage_V[0];
    const double lost_As = (kSoc0 - integ.state()[0]) * kQ * 3600.0;
    const double expected_As = duty * 0.5 * (v0 + v1) / 47.0 * 3600.0;
    EXPECT_NEAR(lost_As, expected_As, 1e-3 * expected_As) << "duty " << duty;
    EXPECT_NEAR(sig.balance_current_A[0], duty * v1 / 47.0, 1e-12) << "duty " << duty;
    RecordProperty(duty < 1.0 ? "lost_As_duty" : "lost_As_on", std::to_string(lost_As));
  }
}

}  // namespace
}  // namespace packsim
