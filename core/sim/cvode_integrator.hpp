// SUNDIALS CVODE as the reference integrator: BDF with the KLU sparse direct linear
// solver on the plant's Jacobian pattern (OdeSystem::jacobianPattern), filled by
// difference quotients with column colouring (core/sim/cvode_jacobian.hpp): per cell
// the cost does not grow with the pack's size. KLU analyses the pattern once and
// refactors numerically at every Jacobian update. Re-initialised only at discontinuities,
// and warmly (reset()): an input that jumps (a relay, a fault, a load step, the active
// balancer's converters every tick) restarts the method at order 1, as the SUNDIALS
// usage notes require after a discontinuity, but keeps what the jump does not make
// stale -- the step size, the last Jacobian while it is young, KLU's symbolic analysis.
//
// Newton::Diagonal replaces the sparse Newton matrix by its diagonal (CVODE's CVDiag: the
// Jacobian's diagonal from one difference quotient along all states at once, so a setup
// costs one right-hand side and O(n), no factorisation). The error test and the Newton
// convergence test are CVODE's own either way, so the answer keeps the tolerances; what
// changes is how fast Newton converges. It pays where setups are many and the coupling
// between states is weak on the scale of CVODE's step: system B's active-balancer race
// restarts CVODE ~10 times a simulated second, each restart forces a setup (and the
// step's regrowth ~3 more), and a sparse setup there refactors 28 dense 45x45 blocks
// (75 % of the run in KLU and the matrix copies); its cells couple through their group's
// current split only by ~1e-4 /s against 1/γ ~ 50 /s at its ~20 ms steps. The same
// steps and setups (3,038 vs 3,046 steps, 2,386 vs 2,383 setups in the first 60 s),
// 8x less CPU. A stiff coupling between states (one that γ·J does not make small)
// converges slower on the diagonal: there the sparse matrix is the choice (default).
//
// A capacitor charged at near-constant power (OdeSystem::squaredState: the active
// balancer's bus, C·dV/dt = P/V) is carried as V² from each restart at which V > 0: V²
// moves on a straight line between two switches, where V bends (V'' = -V'²/V) and its
// error test held each order-1 restart to ~5 steps of ~20 ms on system B's race (the bus
// was the largest weighted error at every tick). Its absolute tolerance is mapped at the
// restart (dV² = 2·V·dV) and rtol on V² is rtol/2 on V, so the bus is held at least as
// tightly; the other states keep theirs. state() is always in the model's coordinates.
// On B's race: 1.7 steps a tick instead of 5.2, CVODE 2.2x the fast integrator's CPU
// instead of 6.2x (bench/README.md).
//
// The caller owns time: advance(t_out, t_stop) returns the solution at t_out and
// never lets CVODE step past t_stop (the next discontinuity). Between calls CVODE
// keeps its history, so ticks shorter than its step cost only an interpolation.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/sim/integrator.hpp"
#include "core/sim/ode_system.hpp"

namespace packsim {

using CvodeStats = SolverStats;

class CvodeIntegrator : public Integrator {
 public:
  enum class Newton { Sparse, Diagonal };
  CvodeIntegrator(OdeSystem& sys, double rtol, Newton newton = Newton::Sparse);
  ~CvodeIntegrator();
  CvodeIntegrator(const CvodeIntegrator&) = delete;
  CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

  // (Re)starts the integration at t from x (length size()).
  void reset(double t, const double* x) override;
  // Integrates to t_out without stepping past t_stop (t_stop >= t_out).
  void advance(double t_out, double t_stop) override;
  const double* state() const override;
  double time() const override { return t_; }
  CvodeStats stats() const override;
  const char* name() const override { return "cvode"; }
  // Outputs inside CVODE's last step (most ticks: its steps are far longer) are its
  // interpolation, formed here from its history with no library call
  // (core/sim/cvode_output.hpp), the same to the bit. Off: every output is CVode's own
  // (the reference the tests compare with). ownOutputs(): how many were formed here.
  void setOwnOutputs(bool on);
  long ownOutputs() const;
  // Never: CVODE's last right-hand side was taken at a trial point inside its step,
  // not at the interpolated t_out, so the loop evaluates the plant itself.
  const PlantSignals* signalsAt(double) const override { return nullptr; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  void noteHistory();
  bool ownOutputInside(double t_out, double t_stop);
  // CVODE's own limit on a Jacobian's age (msbj, steps) also bounds its reuse across restarts.
  static constexpr long kJacobianMaxAgeSteps = 51;
  // First step after a restart, as a fraction of the last step (reset()); on system B's
  // balancer race 0.25 took 1,390 steps per 30 s against 1,521 for 1.0 and 1,613 for
  // CVODE's own estimate.
  static constexpr double kRestartStepFraction = 0.25;
  // Relative change of γ that forms a new Newton matrix (CVodeSetDeltaGammaMaxLSetup):
  // CVODE's default 0.3. Larger saves setups (2: 549 per 30 s of B's balancer race
  // against 1,224) but costs accuracy: at 2 the scooter's energy with and without its
  // FET node differed by 4.4e-6 (FetThermal.*), at 5 a 100 Hz ramp logger's charge
  // drifted to 1.3e-2 As (Breakpoints.*).
  static constexpr double kGammaChangeForSetup = 0.3;
  double t_ = 0.0;
  double lastStep_s_ = 0.0;  // 0: CVODE estimates the first step itself
  long reinits_ = 0;
  CvodeStats base_;
};

}  // namespace packsim
