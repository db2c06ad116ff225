// What an integrator needs from a model: its size, the sparsity of its Jacobian,
// per-component absolute tolerances and the right-hand side.
#pragma once
#include <vector>

#include "core/sim/sparsity.hpp"

namespace packsim {

class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual int size() const = 0;
  // Which states each state's rate depends on (core/sim/sparsity.hpp).
  virtual JacobianPattern jacobianPattern() const = 0;
  virtual std::vector<double> absTolerances() const = 0;
  virtual void rhs(double t, const double* x, double* dx) = 0;
  // For the Jacobian's difference quotients: holdCouplings(t, x0) fixes at x0 what a
  // complete row of the pattern leaves out (a coupling of every state through one
  // scalar, e.g. the pack current under a power load), and rhsHeld(t, x) is the
  // right-hand side with it held there. So the left-out coupling cannot leak into the
  // entries of columns perturbed together; rhsHeld(t, x0) equals rhs(t, x0). Defaults:
  // the pattern leaves nothing out.
  virtual void holdCouplings(double /*t*/, const double* /*x0*/) {}
  virtual void rhsHeld(double t, const double* x, double* dx) { rhs(t, x, dx); }
  // A state an integrator may carry as its square (-1: none): a capacitor's voltage V
  // charged at near-constant power P, C·dV/dt = P/V. V bends (V'' = -V'²/V) where
  // V² = 2·E/C moves linearly in time.
  virtual int squaredState() const { return -1; }
};

}  // namespace packsim
