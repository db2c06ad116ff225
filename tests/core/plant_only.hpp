// The plant alone as an ODE for an integrator, relay closed, at a constant load
// current (positive discharges): the cell closed-form tests integrate this directly.
#pragma once
#include <vector>

#include "core/sim/ode_system.hpp"
#include "core/sim/plant.hpp"

namespace packsim::test {

struct PlantOnly : OdeSystem {
  const Plant& plant;
  PlantInputs in;
  PlantSignals sig;
  PlantOnly(const Plant& p, double current_A) : plant(p), sig(p.makeSignals()) {
    in.relay_closed = true;
    in.load.i0_A = current_A;
  }
  int size() const override { return plant.stateSize(); }
  JacobianPattern jacobianPattern() const override { return plant.jacobianPattern(0); }
  std::vector<double> absTolerances() const override { return std::vector<double>(size(), 1e-12); }
  void rhs(double t, const double* x, double* dx) override { plant.derivatives(t, x, in, dx, sig); }
};

}  // namespace packsim::test
