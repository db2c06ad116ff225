#include "core/sim/plant.hpp"

namespace packsim {

Plant::Plant(const Scenario& s) : initialSoc_(s.pack.initial_soc), initialTemp_C_(s.pack.initial_temp_C) {
  pack_.series = s.pack.series;
  pack_.parallel = s.pack.parallel;
  pack_.cells.assign(static_cast<size_t>(pack_.cellCount()), s.pack.cell);
  pack_.layout.n_rc = static_cast<int>(s.pack.cell.rc.size());
  for (const CellParams& c : pack_.cells) thermal_.addNode(c.heat_capacity_J_per_K, c.g_ambient_W_per_K);
  stride_ = pack_.layout.size() + 1;
  stateSize_ = pack_.cellCount() * stride_ + (thermal_.nodeCount() - pack_.cellCount());
}

int Plant::bandwidth() const { return pack_.parallel * stride_ - 1 + stride_; }

PlantSignals Plant::makeSignals() const {
  PlantSignals s;
  const size_t n = static_cast<size_t>(pack_.cellCount());
  s.cell_current_A.assign(n, 0.0);
  s.cell_voltage_V.assign(n, 0.0);
  s.group_voltage_V.assign(static_cast<size_t>(pack_.series), 0.0);
  s.heat_W.assign(static_cast<size_t>(thermal_.nodeCount()), 0.0);
  s.node_temp_C.assign(static_cast<size_t>(thermal_.nodeCount()), 0.0);
  s.node_rate_K_per_s.assign(static_cast<size_t>(thermal_.nodeCount()), 0.0);
  return s;
}

void Plant::initialState(double* x) const {
  for (int i = 0; i < stateSize_; ++i) x[i] = 0.0;
  for (int c = 0; c < pack_.cellCount(); ++c) {
    x[c * stride_ + CellLayout::soc] = initialSoc_;
    x[tempIndex(c)] = initialTemp_C_;
  }
}

void Plant::evaluate(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const {
  sig.pack_current_A = in.relay_closed ? in.load.current_A(t) : 0.0;
  sig.pack_voltage_V = 0.0;
  auto cellX = [&](int c) { return cellStates(x, c); };
  for (int g = 0; g < pack_.series; ++g) {
    const double v = pack_.splitGroup(g, sig.pack_current_A, cellX, sig.cell_current_A.data());
    sig.group_voltage_V[static_cast<size_t>(g)] = v;
    sig.pack_voltage_V += v;
    for (int k = 0; k < pack_.parallel; ++k) sig.cell_voltage_V[static_cast<size_t>(g * pack_.parallel + k)] = v;
  }
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const size_t ci = static_cast<size_t>(c);
    sig.heat_W[ci] = ecm::heat_W(pack_.cells[ci], cellX(c), sig.cell_current_A[ci]);
    sig.node_temp_C[ci] = x[tempIndex(c)];
  }
}

void Plant::derivatives(double t, const double* x, const PlantInputs& in, double* dx, PlantSignals& sig) const {
  evaluate(t, x, in, sig);
  for (int c = 0; c < pack_.cellCount(); ++c) {
    ecm::derivatives(pack_.cells[static_cast<size_t>(c)], cellStates(x, c), sig.cell_current_A[static_cast<size_t>(c)],
                     dx + c * stride_);
  }
  // Thermal network on gathered temperatures; rates scattered to the state slots.
  thermal_.derivatives(sig.node_temp_C.data(), sig.heat_W.data(), in.ambient_C, sig.node_rate_K_per_s.data());
  for (int c = 0; c < pack_.cellCount(); ++c) dx[tempIndex(c)] = sig.node_rate_K_per_s[static_cast<size_t>(c)];
}

void Plant::quadratures(double t, const double* x, const PlantInputs& in, double* dq, PlantSignals& sig) const {
  evaluate(t, x, in, sig);
  double heat = 0.0, chem = 0.0;
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const size_t ci = static_cast<size_t>(c);
    heat += sig.heat_W[ci];
    chem += ecm::ocv(pack_.cells[ci], x[c * stride_ + CellLayout::soc]) * sig.cell_current_A[ci];
  }
  dq[kQuadCharge_As] = sig.pack_current_A;
  dq[kQuadLoadEnergy_J] = sig.pack_current_A * sig.pack_voltage_V;
  dq[kQuadHeat_J] = heat;
  dq[kQuadChemEnergy_J] = chem;
}

}  // namespace packsim
