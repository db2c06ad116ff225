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

#include "core/sim/simulation.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

TEST(CvodeRestarts, BalancerSwitchesReuseTheJacobianAndTheFactorisation) {
  Scenario s = loadScenarioFile(test::scenarioDir() + "/solar_car_28s15p_balancer.yaml");
  s.run.solver = RunConfig::Solver::Cvode;
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

}  // namespace
}  // namespace packsim
