#include "core/sim/plant_ode.hpp"

namespace packsim {

PlantOde::PlantOde(const Plant& p, const RunConfig& run, const PlantInputs& in)
    : plant_(p), run_(run), in_(in), sig_(p.makeSignals()) {}

int PlantOde::size() const { return plant_.stateSize() + kQuadCount; }
JacobianPattern PlantOde::jacobianPattern() const { return plant_.jacobianPattern(kQuadCount); }
int PlantOde::squaredState() const { return plant_.busIndex(); }

std::vector<double> PlantOde::absTolerances() const {
  std::vector<double> a(static_cast<size_t>(size()), run_.atol_V);
  for (int c = 0; c < plant_.pack().cellCount(); ++c) a[static_cast<size_t>(c * plant_.stride())] = run_.atol_soc;
  for (int j = 0; j < plant_.thermal().nodeCount(); ++j) a[static_cast<size_t>(plant_.tempIndex(j))] = run_.atol_C;
  for (int q = 0; q < kQuadCount; ++q) a[static_cast<size_t>(plant_.stateSize() + q)] = 1e-3;
  return a;
}

void PlantOde::rhs(double t, const double* x, double* dx) {
  plant_.derivatives(t, x, in_, dx, sig_);
  plant_.quadratures(sig_, dx + plant_.stateSize());
}

void PlantOde::holdCouplings(double t, const double* x0) {
  plant_.terminalCurrent(t, x0, in_, sig_);
  heldCurrent_A_ = sig_.pack_current_A;
  heldCharger_A_ = sig_.charger_A;
}

void PlantOde::rhsHeld(double t, const double* x, double* dx) {
  sig_.pack_current_A = heldCurrent_A_;
  sig_.charger_A = heldCharger_A_;
  plant_.derivativesAtCurrent(t, x, in_, dx, sig_);
  plant_.quadratures(sig_, dx + plant_.stateSize());
}

}  // namespace packsim
