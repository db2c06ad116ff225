#include "core/sim/plant.hpp"

#include <algorithm>
#include <cmath>

namespace packsim {

Plant::Plant(const Scenario& s)
    : ambient_(s.ambient_C), coolant_C_(s.thermal.coolant_C), loadQuantity_(s.load.quantity),
      initialTemp_C_(s.pack.initial_temp_C) {
  pack_.series = s.pack.series;
  pack_.parallel = s.pack.parallel;
  pack_.interconnect_ohm = s.pack.interconnect_ohm;
  PackCells cells = drawCells(s.pack.cell, s.pack.initial_soc, pack_.cellCount(), pack_.parallel, s.pack.spread,
                              s.pack.cell_overrides, s.run.seed);
  pack_.cells = std::move(cells.params);
  initialSoc_ = std::move(cells.initial_soc);
  pack_.layout.n_rc = static_cast<int>(s.pack.cell.rc.size());

  const ThermalConfig& th = s.thermal;
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const CellParams& p = pack_.cells[static_cast<size_t>(c)];
    thermal_.addNode("cell " + std::to_string(c + 1), p.heat_capacity_J_per_K, p.g_ambient_W_per_K,
                     th.g_coolant_W_per_K);
  }
  if (th.cell_to_cell_W_per_K > 0.0)
    for (int c = 0; c + 1 < pack_.cellCount(); ++c) thermal_.link(c, c + 1, th.cell_to_cell_W_per_K);
  for (const ThermalNodeConfig& n : th.nodes) {
    const int id = thermal_.addNode(n.name, n.heat_capacity_J_per_K, n.g_ambient_W_per_K);
    if (n.g_each_cell_W_per_K > 0.0)
      for (int c = 0; c < pack_.cellCount(); ++c) thermal_.link(id, c, n.g_each_cell_W_per_K);
    for (const auto& [cell, g] : n.cell_links) thermal_.link(id, cell, g);
  }
  stride_ = pack_.layout.size() + 1;
  stateSize_ = pack_.cellCount() * stride_ + (thermal_.nodeCount() - pack_.cellCount());
}

int Plant::bandwidth() const { return pack_.parallel * stride_ - 1 + stride_; }

int Plant::tempIndex(int node) const {
  const int cells = pack_.cellCount();
  return node < cells ? node * stride_ + pack_.layout.size() : cells * stride_ + (node - cells);
}

PlantSignals Plant::makeSignals() const {
  PlantSignals s;
  const size_t n = static_cast<size_t>(pack_.cellCount());
  const size_t nodes = static_cast<size_t>(thermal_.nodeCount());
  s.cell_current_A.assign(n, 0.0);
  s.cell_voltage_V.assign(n, 0.0);
  s.internal_A.assign(n, 0.0);
  s.group_voltage_V.assign(static_cast<size_t>(pack_.series), 0.0);
  s.heat_W.assign(nodes, 0.0);
  s.node_temp_C.assign(nodes, 0.0);
  s.node_rate_K_per_s.assign(nodes, 0.0);
  return s;
}

void Plant::initialState(double* x) const {
  for (int i = 0; i < stateSize_; ++i) x[i] = 0.0;
  for (int c = 0; c < pack_.cellCount(); ++c) x[c * stride_ + CellLayout::soc] = initialSoc_[static_cast<size_t>(c)];
  for (int j = 0; j < thermal_.nodeCount(); ++j) x[tempIndex(j)] = initialTemp_C_;
}

// The load's current; a power load solves P = (E - R·I)·I for the smaller root and
// is held at the maximum power point E/(2R) if P exceeds E²/(4R).
double Plant::packCurrent(double t, const PlantInputs& in, double e_V, double r_ohm, bool& limited) const {
  limited = false;
  if (!in.relay_closed) return in.precharge_A;
  const double extra = in.faults ? in.faults->extra_load_A : 0.0;
  const double demand = in.load.current_A(t);
  if (loadQuantity_ == LoadProfile::Quantity::Current_A) return demand + extra;
  const double disc = e_V * e_V - 4.0 * r_ohm * demand;
  if (disc < 0.0) {
    limited = true;
    return e_V / (2.0 * r_ohm) + extra;
  }
  return 2.0 * demand / (e_V + std::sqrt(disc)) + extra;  // stable form of (E - √disc)/(2R)
}

void Plant::evaluate(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const {
  auto cellX = [&](int c) { return cellStates(x, c); };
  if (loadQuantity_ == LoadProfile::Quantity::Power_W && in.relay_closed) {
    double e = 0.0, r = pack_.interconnect_ohm;
    for (int g = 0; g < pack_.series; ++g) {
      double eg = 0.0, rg = 0.0;
      pack_.groupThevenin(g, cellX, eg, rg);
      e += eg;
      r += rg;
    }
    sig.pack_current_A = packCurrent(t, in, e, r, sig.power_limited);
  } else {
    sig.pack_current_A = packCurrent(t, in, 0.0, 0.0, sig.power_limited);
  }
  if ((sig.pack_current_A > 0.0 && in.discharge_blocked) || (sig.pack_current_A < 0.0 && in.charge_blocked))
    sig.pack_current_A = 0.0;
  sig.pack_voltage_V = -sig.pack_current_A * pack_.interconnect_ohm;
  for (int g = 0; g < pack_.series; ++g) {
    const double v = pack_.splitGroup(g, sig.pack_current_A, cellX, sig.cell_current_A.data());
    sig.group_voltage_V[static_cast<size_t>(g)] = v;
    sig.pack_voltage_V += v;
    for (int k = 0; k < pack_.parallel; ++k) sig.cell_voltage_V[static_cast<size_t>(g * pack_.parallel + k)] = v;
  }
  const HardwareFaults* f = in.faults;
  sig.injected_heat_W = 0.0;
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const size_t ci = static_cast<size_t>(c);
    const CellParams& p = pack_.cells[ci];
    double q = ecm::heat_W(p, cellX(c), sig.cell_current_A[ci]);
    sig.internal_A[ci] = 0.0;
    if (f) {
      if (ci < f->cell_heat_W.size()) {
        q += f->cell_heat_W[ci];
        sig.injected_heat_W += f->cell_heat_W[ci];
      }
      if (ci < f->cell_leak_ohm.size() && f->cell_leak_ohm[ci] > 0.0) {
        // An internal short: a resistance across the cell's EMF, inside its terminals.
        const double i_int = ecm::ocv(p, cellX(c)[CellLayout::soc]) / f->cell_leak_ohm[ci];
        sig.internal_A[ci] = i_int;
        q += i_int * i_int * f->cell_leak_ohm[ci];
      }
    }
    sig.heat_W[ci] = q;
  }
  for (int j = 0; j < thermal_.nodeCount(); ++j) {
    if (j >= pack_.cellCount()) sig.heat_W[static_cast<size_t>(j)] = 0.0;
    sig.node_temp_C[static_cast<size_t>(j)] = x[tempIndex(j)];
  }
  sig.ambient_C = ambient_.at(t);
}

void Plant::derivatives(double t, const double* x, const PlantInputs& in, double* dx, PlantSignals& sig) const {
  evaluate(t, x, in, sig);
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const size_t ci = static_cast<size_t>(c);
    ecm::derivatives(pack_.cells[ci], cellStates(x, c), sig.cell_current_A[ci], dx + c * stride_, sig.internal_A[ci]);
  }
  // Thermal network on gathered temperatures; rates scattered to the state slots.
  thermal_.derivatives(sig.node_temp_C.data(), sig.heat_W.data(), sig.ambient_C, coolant_C_,
                       sig.node_rate_K_per_s.data());
  for (int j = 0; j < thermal_.nodeCount(); ++j) dx[tempIndex(j)] = sig.node_rate_K_per_s[static_cast<size_t>(j)];
}

void Plant::quadratures(const double* x, const PlantSignals& sig, double* dq) const {
  // Joule heat only: heat injected by a scripted fault is not drawn from the cells.
  double heat = sig.pack_current_A * sig.pack_current_A * pack_.interconnect_ohm - sig.injected_heat_W, chem = 0.0;
  for (int j = 0; j < thermal_.nodeCount(); ++j) heat += sig.heat_W[static_cast<size_t>(j)];
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const size_t ci = static_cast<size_t>(c);
    chem += ecm::ocv(pack_.cells[ci], x[c * stride_ + CellLayout::soc]) * (sig.cell_current_A[ci] + sig.internal_A[ci]);
  }
  dq[kQuadCharge_As] = sig.pack_current_A;
  dq[kQuadLoadEnergy_J] = sig.pack_current_A * sig.pack_voltage_V;
  dq[kQuadHeat_J] = heat;
  dq[kQuadChemEnergy_J] = chem;
}

std::vector<Plant::RcBranch> Plant::rcBranches() const {
  std::vector<RcBranch> b;
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const CellParams& p = pack_.cells[static_cast<size_t>(c)];
    for (int k = 0; k < pack_.layout.n_rc; ++k)
      b.push_back({c * stride_ + pack_.layout.rc(k), p.rc[static_cast<size_t>(k)].tau_s()});
  }
  return b;
}

// Thermal node j: by Gershgorin, the eigenvalues of its row of the network lie within
// (G_amb + G_cool + 2·Σ G_link)/C_j, so τ_j = C_j / that sum bounds it from below.
// Parallel groups: a cell's current I_i = (E_i - V_g)/R0_i feeds back on its own
// state through E_i: on an RC voltage with rate 1/(C_k·R0) and on SOC with rate
// |dOCV/dSOC| / (3600·Q·R0). (Series cells carry the load current, which does not
// depend on their state; a constant-power load's weak I(V) feedback is ignored.)
double Plant::explicitTimeConstant_s() const {
  double tau = INFINITY;
  const int nodes = thermal_.nodeCount();
  std::vector<double> g(static_cast<size_t>(nodes), 0.0);
  for (int j = 0; j < nodes; ++j)
    g[static_cast<size_t>(j)] = thermal_.g_ambient_W_per_K[static_cast<size_t>(j)] +
                                thermal_.g_coolant_W_per_K[static_cast<size_t>(j)];
  for (const ThermalLink& l : thermal_.links) {
    g[static_cast<size_t>(l.a)] += 2.0 * l.g_W_per_K;
    g[static_cast<size_t>(l.b)] += 2.0 * l.g_W_per_K;
  }
  for (int j = 0; j < nodes; ++j)
    if (g[static_cast<size_t>(j)] > 0.0)
      tau = std::min(tau, thermal_.heat_capacity_J_per_K[static_cast<size_t>(j)] / g[static_cast<size_t>(j)]);
  if (pack_.parallel > 1) {
    constexpr int kGrid = 200;
    for (const CellParams& p : pack_.cells) {
      double r0_min = INFINITY, slope_max = 0.0, prev = ecm::ocv(p, 0.0);
      for (int i = 0; i <= kGrid; ++i) {
        const double soc = static_cast<double>(i) / kGrid;
        r0_min = std::min(r0_min, ecm::r0(p, soc));
        if (i > 0) {
          const double v = ecm::ocv(p, soc);
          slope_max = std::max(slope_max, std::fabs(v - prev) * kGrid);
          prev = v;
        }
      }
      if (!(r0_min > 0.0)) continue;
      if (slope_max > 0.0) tau = std::min(tau, 3600.0 * p.capacity_Ah * r0_min / slope_max);
      for (const RcPair& rc : p.rc) tau = std::min(tau, rc.c_F * r0_min);
    }
  }
  return tau;
}

}  // namespace packsim
