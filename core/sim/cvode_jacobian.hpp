// A sparse Jacobian df/dx filled by difference quotients with column colouring
// (core/sim/sparsity.hpp): one right-hand side per colour, whatever the size of the
// system. Column j moves by srur·max(|x_j|, 1/w_j) (srur = √unit roundoff, w the
// integrator's error weights), the increment CVODE's own difference quotients use.
#pragma once
#include <vector>

#include "core/sim/ode_system.hpp"
#include "core/sim/sparsity.hpp"

namespace packsim {

class ColouredJacobian {
 public:
  explicit ColouredJacobian(JacobianPattern p);
  const JacobianPattern& pattern() const { return p_; }
  int colourCount() const { return static_cast<int>(groups_.size()); }
  long rhsEvals() const { return rhsEvals_; }  // right-hand sides spent filling, in all

  // values[k] for the pattern's k-th entry, at (t, x) with f0 = f(t, x) and error
  // weights w. x1 and f1 are work arrays of length n.
  void fill(OdeSystem& sys, double t, const double* x, const double* f0, const double* w, double* x1, double* f1,
            double* values);

 private:
  JacobianPattern p_;
  std::vector<std::vector<int>> groups_;
  std::vector<double> inc_;
  long rhsEvals_ = 0;
};

}  // namespace packsim
