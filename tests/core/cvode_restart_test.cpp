// CVODE's restarts at input switches (core/sim/cvode_integrator.hpp, reset()): system B's
// race with its active balancer switches a 3 A converter on or off nearly every 100 ms
// tick (the controller picks the highest and lowest module from noisy readings, and the
// small bus fills and empties), so CVODE is re-initialised ~10 times per simulated
// second. Each restart is at order 1 (the SUNDIALS usage notes: history from before a
// discontinuity must be dropped), but it must not cost what a cold start costs: before
// this, every restart evaluated a new Jacobian by difference quotients (47 right-hand
// sides on this pack), and formed and factored the Newton matrix 4.6 times (the first
// after a fresh symbolic analysis), 26 ms per restart, 9 minutes for the race.
//
// The counters below are the oracle, not a time: they come from CVODE's own statistics
// (CVodeGetNumJacEvals, CVodeGetNumLinSolvSetups) and the difference quotients' count.
// Measured over 60 s: 594 restarts, 54 Jacobian evaluations (541 restarts reused one),
// 4.0 Newton-matrix setups per restart; with the bus voltage carried as its square
// (2026-11-26), 25 Jacobians (570 reused), 2.0 setups and 2.0 steps per restart. Before: 593 Jacobian evaluations (one per
// restart) and 4.6 setups per restart (2,730). The setups stay at CVODE's own threshold
// (a γ change of 0.3): at 2 they fell to 1.85 per restart, but the scooter's energy with
// and without its FET node then differed by 4.4e-6 (FetThermal.*; 1e-7 at 0.3).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/sim/cvode_integrator.hpp"
#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

TEST(CvodeRestarts, BalancerSwitchesReuseTheJacobianAndTheFactorisation) {
  Scenario s = loadScenarioFile(test::scenarioDir() + "/solar_car_28s15p_balancer.yaml");
  s.run.solver = RunConfig::Solver::Cvode;
  s.run.jacobian = RunConfig::Jacobian::Sparse;  // the diagonal: the test below
  s.run.duration_s = 60.0;
  s.compare_scenario.clear();
  const RunResult r = runScenario(s);
  const SolverStats& st = r.solver;
  const double sim_s = r.rec.time_s.back();
  std::printf("60 s: %ld restarts, %ld steps, %ld Jacobians (%ld reused), %ld setups, %ld rhs + %ld for Jacobians\n",
              st.reinits, st.steps, st.jac_evals, st.jac_reused, st.lin_setups, st.rhs_evals, st.jac_rhs_evals);
  // The scenario does exercise restarts: the converters switch at most ticks.
  EXPECT_GT(static_cast<double>(st.reinits), 5.0 * sim_s);
  // A restart keeps the last Jacobian while it is younger than CVODE's own reuse limit.
  EXPECT_GT(st.jac_reused, st.reinits / 2);
  EXPECT_LT(st.jac_evals, st.reinits / 4);
  // The Newton matrix: fewer setups than before (4.6 a restart, then 4.0 with the step
  // starting from a quarter of the last one instead of a cold estimate), and ~2 steps a
  // restart since the bus is carried as its square (OdeSystem::squaredState; 5.1 in V:
  // 3,046 steps and 2,382 setups in these 60 s, now 1,175 and 1,170).
  EXPECT_LT(static_cast<double>(st.lin_setups), 2.5 * static_cast<double>(st.reinits));
  EXPECT_LT(static_cast<double>(st.steps), 2.5 * static_cast<double>(st.reinits));
  // The difference quotients cost fewer right-hand sides than the steps themselves.
  EXPECT_LT(st.jac_rhs_evals, st.rhs_evals);
}

// The diagonal Newton matrix (run.jacobian: diagonal, CVODE's CVDiag), the one to run
// this scenario on CVODE with: no Jacobian, no factorisation, one right-hand side per setup. Independent
// expectation: the answer is the sparse matrix's within the tolerances, because the
// Newton matrix changes only how fast Newton converges, not CVODE's error test. Over
// 30 s (~300 restarts) both runs take the same converter decisions (a 45 mV step in a
// module's voltage otherwise), so the truths can be held to far below any sensor's
// resolution: cell voltages and SOC to 1e-6 V and 1e-8, the bus to 1e-3 V (rtol 1e-6
// of 2.5-5 V per step, summed over ~1,500 steps).
TEST(CvodeRestarts, DiagonalNewtonMatrixNeedsNoJacobianAndGivesTheSparseAnswer) {
  Scenario s = loadScenarioFile(test::scenarioDir() + "/solar_car_28s15p_balancer.yaml");
  s.run.solver = RunConfig::Solver::Cvode;
  s.run.jacobian = RunConfig::Jacobian::Diagonal;
  s.run.duration_s = 30.0;
  s.compare_scenario.clear();
  const RunResult diag = runScenario(s);
  s.run.jacobian = RunConfig::Jacobian::Sparse;
  const RunResult sparse = runScenario(s);
  const SolverStats& d = diag.solver;
  std::printf("30 s diagonal: %ld restarts, %ld steps, %ld setups, %ld rhs + %ld for setups; sparse: %ld steps, %ld setups\n",
              d.reinits, d.steps, d.lin_setups, d.rhs_evals, d.jac_rhs_evals, sparse.solver.steps,
              sparse.solver.lin_setups);
  EXPECT_GT(static_cast<double>(d.reinits), 5.0 * 30.0);  // the converters did switch
  EXPECT_EQ(d.jac_evals, 0);
  EXPECT_EQ(d.jac_reused, 0);
  EXPECT_EQ(d.jac_rhs_evals, d.lin_setups);  // CVDiag: one difference quotient per setup
  const Recording& a = diag.rec;
  const Recording& b = sparse.rec;
  ASSERT_EQ(a.samples(), b.samples());
  ASSERT_EQ(a.balance_current_A, b.balance_current_A);  // the same decisions at every sample
  double dV = 0.0, dSoc = 0.0, dBus = 0.0;
  for (size_t i = 0; i < a.cell_voltage_V.size(); ++i) {
    dV = std::max(dV, std::fabs(a.cell_voltage_V[i] - b.cell_voltage_V[i]));
    dSoc = std::max(dSoc, std::fabs(a.cell_soc[i] - b.cell_soc[i]));
  }
  for (size_t i = 0; i < a.balancer_bus_V.size(); ++i) dBus = std::max(dBus, std::fabs(a.balancer_bus_V[i] - b.balancer_bus_V[i]));
  std::printf("diagonal vs sparse: cell %.2e V, SOC %.2e, bus %.2e V\n", dV, dSoc, dBus);
  EXPECT_LT(dV, 1e-6);
  EXPECT_LT(dSoc, 1e-8);
  EXPECT_LT(dBus, 1e-3);
}

// A capacitor charged and drained at constant power between switches, C·dV/dt = P/V,
// and a decoupled decay dy/dt = -y/τ beside it: the closed forms V² = V0² + 2·P·Δt/C and
// y = y0·exp(-Δt/τ) are the oracle. P switches every 100 ms tick (+8 W, -5 W, as a
// converter into and out of the balancer's bus) and CVODE restarts at each switch.
class PoweredCapacitor : public OdeSystem {
 public:
  explicit PoweredCapacitor(bool squared) : squared_(squared) {}
  static constexpr double kC_F = 2.5, kTau_s = 300.0;
  double power_W = 0.0;
  int size() const override { return 2; }
  JacobianPattern jacobianPattern() const override { return PatternBuilder(2).build(2, 2); }
  std::vector<double> absTolerances() const override { return {1e-6, 1e-6}; }
  void rhs(double, const double* x, double* dx) override {
    dx[0] = power_W / (kC_F * x[0]);
    dx[1] = -x[1] / kTau_s;
  }
  int squaredState() const override { return squared_ ? 0 : -1; }

 private:
  bool squared_;
};

struct CapacitorRun {
  double worstV = 0.0, worstY = 0.0;  // largest relative error against the closed form
  SolverStats stats;
};

CapacitorRun runCapacitor(bool squared, CvodeIntegrator::Newton newton) {
  PoweredCapacitor sys(squared);
  CvodeIntegrator cv(sys, 1e-6, newton);
  const double x0[2] = {3.5, 1.0};
  cv.reset(0.0, x0);
  double v2 = x0[0] * x0[0], y = x0[1];
  CapacitorRun r;
  const double tick_s = 0.1;
  for (int k = 0; k < 600; ++k) {
    sys.power_W = (k / 3) % 2 == 0 ? 8.0 : -5.0;  // three ticks each way: 3.5 V .. 3.7 V
    if (k > 0) cv.reset(k * tick_s, cv.state());
    cv.advance((k + 1) * tick_s, (k + 1) * tick_s + 60.0);
    v2 += 2.0 * sys.power_W * tick_s / PoweredCapacitor::kC_F;
    y *= std::exp(-tick_s / PoweredCapacitor::kTau_s);
    r.worstV = std::max(r.worstV, std::fabs(cv.state()[0] - std::sqrt(v2)) / std::sqrt(v2));
    r.worstY = std::max(r.worstY, std::fabs(cv.state()[1] - y) / y);
  }
  r.stats = cv.stats();
  return r;
}

// OdeSystem::squaredState: CVODE carries the capacitor's V² (a straight line between
// switches) instead of V (which bends, V'' = -V'²/V). Both meet the closed form to the
// tolerance, V² exactly; V² takes fewer than half the steps (here 1,201 against 2,875):
// on the balancer's bus the error test on V's bend held CVODE to ~5 steps a tick
// (system B's race: 5.2 a tick before, 1.7 after).
TEST(CvodeRestarts, ACapacitorAtConstantPowerIsIntegratedAsItsSquare) {
  for (CvodeIntegrator::Newton newton : {CvodeIntegrator::Newton::Diagonal, CvodeIntegrator::Newton::Sparse}) {
    const CapacitorRun inV = runCapacitor(false, newton), inV2 = runCapacitor(true, newton);
    std::printf("600 switches, %s: in V %ld steps (error %.1e, decay %.1e), in V^2 %ld steps (error %.1e, decay %.1e)\n",
                newton == CvodeIntegrator::Newton::Diagonal ? "diagonal" : "sparse", inV.stats.steps, inV.worstV,
                inV.worstY, inV2.stats.steps, inV2.worstV, inV2.worstY);
    EXPECT_EQ(inV2.stats.reinits, 600);  // the start and every switch
    // In V the local errors of ~5 order-1 steps a tick add up (measured 4.7e-4 after 60 s);
    // the line V² is what backward Euler integrates exactly (measured 4e-15).
    EXPECT_LT(inV.worstV, 1e-3);
    EXPECT_LT(inV2.worstV, 1e-9);
    EXPECT_LT(inV.worstY, 1e-4);
    EXPECT_LT(inV2.worstY, 1e-4);  // the other state is held to the same tolerance
    EXPECT_LT(2 * inV2.stats.steps, inV.stats.steps);
  }
}

}  // namespace
}  // namespace packsim
