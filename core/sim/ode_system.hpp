// What an integrator needs from a model: its size, the half-bandwidth of its
// Jacobian, per-component absolute tolerances and the right-hand side.
#pragma once
#include <vector>

namespace packsim {

class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual int size() const = 0;
  virtual int halfBandwidth() const = 0;
  virtual std::vector<double> absTolerances() const = 0;
  virtual void rhs(double t, const double* x, double* dx) = 0;
};

}  // namespace packsim
