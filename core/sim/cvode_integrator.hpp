// SUNDIALS CVODE as the reference integrator: BDF with the KLU sparse direct linear
// solver on the plant's Jacobian pattern (OdeSystem::jacobianPattern), filled by
// difference quotients with column colouring (core/sim/cvode_jacobian.hpp): per cell
// the cost does not grow with the pack's size. KLU analyses the pattern once and
// refactors numerically at every Jacobian update. Re-initialised only at discontinuities.
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
  CvodeIntegrator(OdeSystem& sys, double rtol);
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
  // Never: CVODE's last right-hand side was taken at a trial point inside its step,
  // not at the interpolated t_out, so the loop evaluates the plant itself.
  const PlantSignals* signalsAt(double) const override { return nullptr; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double t_ = 0.0;
  long reinits_ = 0;
  CvodeStats base_;
};

}  // namespace packsim
