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
// 4.0 Newton-matrix setups per restart. Before: 593 Jacobian evaluations (one per
// restart) and 4.6 setups per restart (2,730). The setups stay at CVODE's own threshold
// (a γ change of 0.3): at 2 they fell to 1.85 per restart, but the scooter's energy with
// and without its FET node then differed by 4.4e-6 (FetThermal.*; 1e-7 at 0.3).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

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
  // The Newton matrix: fewer setups than before (4.6 a restart), the step starting from
  // a quarter of the last one instead of a cold estimate.
  EXPECT_LT(static_cast<double>(st.lin_setups), 4.4 * static_cast<double>(st.reinits));
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

}  // namespace
}  // namespace packsim
