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
  // States [0, bandedSize()) couple only within halfBandwidth(). The rest (quadratures,
  // a thermal node linked to every cell) may depend on any state; the Jacobian keeps
  // only their in-band entries, found by perturbing each of them alone.
  virtual int bandedSize() const { return size(); }
  virtual std::vector<double> absTolerances() const = 0;
  virtual void rhs(double t, const double* x, double* dx) = 0;
};

}  // namespace packsim
