// The plant plus its energy quadratures as one ODE for the CVODE adapter
// (core/sim/cvode_integrator.hpp):
//
//   x = [plant states…, charge_As, load_J, heat_J, chem_J]
//   dx/dt = [Plant::derivatives(t, x, inputs), Plant::quadratures(signals at x)]
//
// Absolute tolerances per component: run.atol_soc on each cell's SOC, run.atol_C on
// every thermal node, 1e-3 on the quadratures (C, J) and run.atol_V on the rest (RC
// voltages, hysteresis). The inputs are read at every evaluation; the loop changes them
// only before an integrator reset.
#pragma once
#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/ode_system.hpp"
#include "core/sim/plant.hpp"

namespace packsim {

class PlantOde : public OdeSystem {
 public:
  PlantOde(const Plant& p, const RunConfig& run, const PlantInputs& in);

  int size() const override;
  // The plant's (Plant::jacobianPattern); the quadratures are loose rows nothing reads.
  JacobianPattern jacobianPattern() const override;
  std::vector<double> absTolerances() const override;
  void rhs(double t, const double* x, double* dx) override;
  // Holds the pack current (Plant::terminalCurrent) at x0.
  void holdCouplings(double t, const double* x0) override;
  void rhsHeld(double t, const double* x, double* dx) override;
  // The active balancer's bus: its converters move the stored energy at a near-constant
  // power between two switches (Plant::busIndex).
  int squaredState() const override;

 private:
  const Plant& plant_;
  const RunConfig& run_;
  const PlantInputs& in_;
  PlantSignals sig_;
  double heldCurrent_A_ = 0.0, heldCharger_A_ = 0.0;
};

}  // namespace packsim
