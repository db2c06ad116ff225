#include "core/sim/plant.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/sim/scenario_cells.hpp"
#include "models/hw/charger.hpp"
#include "models/hw/mosfet.hpp"

namespace packsim {

Plant::Plant(const Scenario& s)
    : ambient_(s.ambient_C), coolant_C_(s.thermal.coolant_C), loadQuantity_(s.load.quantity),
      initialTemp_C_(s.pack.initial_temp_C) {
  ambientFixed_ = ambient_.t_s.size() == 1 && ambient_.value.size() == 1;
  pack_.series = s.pack.series;
  pack_.parallel = s.pack.parallel;
  pack_.interconnect_ohm = s.pack.interconnect_ohm;
  PackCells cells = scenarioCells(s);
  pack_.cells = std::move(cells.params);
  initialSoc_ = std::move(cells.initial_soc);
  pack_.layout.n_rc = static_cast<int>(s.pack.cell.rc.size());
  pack_.layout.hysteresis = s.pack.cell.has_hysteresis;
  pack_.cacheTemperatureUse();
  for (const CellParams& p : pack_.cells) flat_.push_back(FlatCell::of(p));

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
    if (n.heat_W > 0.0) externalHeat_W_.emplace_back(id, n.heat_W);
    if (n.g_each_cell_W_per_K > 0.0)
      for (int c = 0; c < pack_.cellCount(); ++c) thermal_.link(id, c, n.g_each_cell_W_per_K);
    for (const auto& [cell, g] : n.cell_links) thermal_.link(id, cell, g);
  }
  for (const ThermalNodeConfig& n : th.nodes)
    for (const auto& [other, g] : n.node_links) thermal_.link(thermal_.find(n.name), thermal_.find(other), g);
  // One node per monitor board: the named node is the first board's; the others are
  // copies of it (same heat capacity, conductance to ambient and links to other nodes,
  // e.g. the enclosure each board sits on; no links to cells).
  const PassiveBalancerConfig& bal = s.hardware.balancing;
  if (bal.present && !bal.board_node.empty())
    for (const ThermalNodeConfig& n : th.nodes)
      if (n.name == bal.board_node)
        for (int b = 0; b < bal.boardOf(pack_.series - 1) + 1; ++b) {
          if (b == 0) {
            boardNodes_.push_back(thermal_.find(n.name));
            continue;
          }
          const int copy = thermal_.addNode(bal.boardNodeName(b), n.heat_capacity_J_per_K, n.g_ambient_W_per_K);
          for (const auto& [other, g] : n.node_links) thermal_.link(copy, thermal_.find(other), g);
          boardNodes_.push_back(copy);
        }
  stride_ = pack_.layout.size() + 1;
  stateSize_ = pack_.cellCount() * stride_ + (thermal_.nodeCount() - pack_.cellCount());
  balancer_ = s.hardware.balancing;
  if (balancer_.present && !balancer_.board_node.empty()) boardNode_ = thermal_.find(balancer_.board_node);
  fet_[0] = s.hardware.discharge_fet;
  fet_[1] = s.hardware.charge_fet;
  fetPaths_ = s.hardware.fet_paths;
  for (int k = 0; k < 2; ++k)
    if (fet_[k].present && !fet_[k].thermal_node.empty()) fetNode_[k] = thermal_.find(fet_[k].thermal_node);
  fetHeats_ = fetNode_[0] >= 0 || fetNode_[1] >= 0;
  active_ = s.hardware.active_balancer;
  if (active_.present) busIndex_ = stateSize_++;
  for (int j = 0; j < thermal_.nodeCount(); ++j) tempState_.push_back(tempIndex(j));
}

PlantSignals Plant::makeSignals() const {
  PlantSignals s;
  const size_t n = static_cast<size_t>(pack_.cellCount());
  const size_t nodes = static_cast<size_t>(thermal_.nodeCount());
  s.cell_current_A.assign(n, 0.0);
  s.cell_voltage_V.assign(n, 0.0);
  s.internal_A.assign(n, 0.0);
  s.cell_ocv_V.assign(n, 0.0);
  s.cell_r0_ohm.assign(n, 0.0);
  s.cell_emf_V.assign(n, 0.0);
  s.cell_reversible_W.assign(n, 0.0);
  s.cell_hints.assign(n, CellHints{});
  s.group_voltage_V.assign(static_cast<size_t>(pack_.series), 0.0);
  s.heat_W.assign(nodes, 0.0);
  s.balance_current_A.assign(static_cast<size_t>(pack_.series), 0.0);
  s.node_temp_C.assign(nodes, 0.0);
  s.node_rate_K_per_s.assign(nodes, 0.0);
  return s;
}

void Plant::initialState(double* x) const {
  for (int i = 0; i < stateSize_; ++i) x[i] = 0.0;
  for (int c = 0; c < pack_.cellCount(); ++c) x[c * stride_ + CellLayout::soc] = initialSoc_[static_cast<size_t>(c)];
  for (int j = 0; j < thermal_.nodeCount(); ++j) x[tempIndex(j)] = initialTemp_C_;
  if (busIndex_ >= 0) x[busIndex_] = active_.bus_initial_V;
}

namespace {

// The active balancer's module-side current of group gi (0 without a converter there).
double converterA(const PlantInputs& in, size_t gi) { return gi < in.converter_A.size() ? in.converter_A[gi] : 0.0; }

}  // namespace

bool Plant::balancingOn(const PlantInputs& in, size_t gi) const {
  return balancer_.present && gi < in.balancing.size() && in.balancing[gi] != 0;
}

double Plant::balancingDuty(const PlantInputs& in, size_t gi) const {
  return gi < in.balance_duty.size() ? in.balance_duty[gi] : 1.0;
}

// A switch that conducts a share d of the time carries d·V/R on average: the branch's
// conductance times d (d = 1: the switch always on).
double Plant::balancingFactor(const PlantInputs& in, int g, double r_g) const {
  const size_t gi = static_cast<size_t>(g);
  return balancingOn(in, gi) ? 1.0 / (1.0 + r_g * balancingDuty(in, gi) / balancer_.branch_ohm()) : 1.0;
}

// V_pack = Σ_g k_g·(E_g - R_g·(I + I_x,g)) - R_ic·I = E - R·I, with the converter
// currents I_x,g held (the bus precharge current is left out: it is small and brief).
template <typename CellX>
void Plant::packThevenin(const PlantInputs& in, CellX cellX, double& e_V, double& r_ohm) const {
  e_V = 0.0;
  r_ohm = pack_.interconnect_ohm;
  for (int g = 0; g < pack_.series; ++g) {
    double eg = 0.0, rg = 0.0;
    pack_.groupThevenin(g, cellX, eg, rg, in.charger_limit_A > 0.0 ? -1.0 : 1.0);
    const double ix = converterA(in, static_cast<size_t>(g));
    const double k = balancingFactor(in, g, rg);
    e_V += k * (eg - rg * ix);
    r_ohm += k * rg;
  }
}

// The load's current; a power load solves P = (E - R·I)·I for the smaller root and
// is held at the maximum power point E/(2R) if P exceeds E²/(4R).
// Always inlined (into currentAtTerminals): for a current load it is a few loads and an
// add, which the out-of-line call doubled (some 15 instructions a plant evaluation).
[[gnu::always_inline]] inline double Plant::packCurrent(double t, const PlantInputs& in, double e_V, double r_ohm) const {
  if (!in.relay_closed) return in.precharge_A;
  const double extra = in.faults ? in.faults->extra_load_A : 0.0;
  const double demand = in.load.current_A(t);
  if (loadQuantity_ == LoadProfile::Quantity::Current_A) return demand + extra;
  const double disc = e_V * e_V - 4.0 * r_ohm * demand;
  if (disc < 0.0) return e_V / (2.0 * r_ohm) + extra;
  return 2.0 * demand / (e_V + std::sqrt(disc)) + extra;  // stable form of (E - √disc)/(2R)
}

[[gnu::always_inline]] inline void Plant::currentAtTerminals(double t, const double* x, const PlantInputs& in,
                                                              PlantSignals& sig) const {
  auto cellX = [&](int c) { return cellStates(x, c); };
  const bool charger = in.relay_closed && in.charger_limit_A > 0.0;
  sig.charger_A = 0.0;
  if ((loadQuantity_ == LoadProfile::Quantity::Power_W && in.relay_closed) || charger) {
    double e = 0.0, r = 0.0;
    packThevenin(in, cellX, e, r);
    sig.pack_current_A = packCurrent(t, in, e, r);
    if (charger) {  // CC-CV on top of whatever else the terminals feed
      sig.charger_A = chargerCurrent_A(in.charger_limit_A, in.charger_setpoint_V, e - r * sig.pack_current_A, r);
      sig.pack_current_A -= sig.charger_A;
    }
  } else {
    sig.pack_current_A = packCurrent(t, in, 0.0, 0.0);
  }
  if ((sig.pack_current_A > 0.0 && in.discharge_blocked) || (sig.pack_current_A < 0.0 && in.charge_blocked)) {
    sig.pack_current_A = 0.0;
    sig.charger_A = 0.0;
  }
}

void Plant::terminalCurrent(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const {
  currentAtTerminals(t, x, in, sig);
}

void Plant::thevenin(const double* x, const PlantInputs& in, double& e_V, double& r_ohm) const {
  packThevenin(in, [&](int c) { return cellStates(x, c); }, e_V, r_ohm);
}

void Plant::evaluate(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const {
  currentAtTerminals(t, x, in, sig);
  evaluateAtCurrent<true>(t, x, in, sig);
}

void Plant::sample(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const {
  currentAtTerminals(t, x, in, sig);
  evaluateAtCurrent<false>(t, x, in, sig);
}

// Always inlined into its four callers (evaluate, sample, derivatives,
// derivativesAtCurrent): the fast integrator's sub-step evaluated a one-cell plant in
// about 330 instructions, of which the call and its register saves were some 30.
template <bool kHeat>
[[gnu::always_inline]] inline void Plant::evaluateAtCurrent(double t, const double* x, const PlantInputs& in,
                                                             PlantSignals& sig) const {
  if constexpr (kHeat) sig.injected_heat_W = 0.0;
  groupCurrents<kHeat>(x, in, sig);  // with each cell's temperature (and heat)
  // The monitor ICs' thermistor bias: a few mA from some groups' cells, spread over the
  // group's parallel cells like a leak; its power heats them (mW: negligible).
  if constexpr (kHeat)
    for (size_t g = 0; g < in.bias_A.size(); ++g) {
      if (in.bias_A[g] == 0.0) continue;
      for (int k = 0; k < pack_.parallel; ++k) {
        const size_t ci = g * static_cast<size_t>(pack_.parallel) + static_cast<size_t>(k);
        const double i = in.bias_A[g] / pack_.parallel;
        sig.internal_A[ci] += i;
        sig.heat_W[ci] += sig.cell_ocv_V[ci] * i;
      }
    }
  for (int j = pack_.cellCount(); j < thermal_.nodeCount(); ++j) {  // the nodes after the cells
    if constexpr (kHeat) sig.heat_W[static_cast<size_t>(j)] = 0.0;
    sig.node_temp_C[static_cast<size_t>(j)] = x[tempIndex(j)];
  }
  if constexpr (kHeat) {
    // Heat from outside the pack (sun on its skin, a motor nearby): not the cells' energy.
    for (const auto& [node, q] : externalHeat_W_) {
      sig.heat_W[static_cast<size_t>(node)] += q;
      sig.injected_heat_W += q;
    }
    // Each resistor heats the board it sits on.
    if (boardNode_ >= 0 && busIndex_ < 0)
      for (int g = 0; g < pack_.series; ++g) {
        const size_t gi = static_cast<size_t>(g);
        sig.heat_W[static_cast<size_t>(boardNodeOfGroup(g))] += sig.group_voltage_V[gi] * sig.balance_current_A[gi];
      }
    // The FETs carry the pack current between the terminals and the load (fetHeats_: one
    // test for a plant whose FETs have no thermal node, instead of the loop's).
    sig.fet_heat_W = 0.0;
    if (fetHeats_) {
      const bool gate[2] = {in.discharge_fet_on, in.charge_fet_on};
      for (int k = 0; k < 2; ++k)
        if (fetNode_[k] >= 0) {
          const double q = mosfetLoss_W(fet_[k], gate[k], fetCurrent_A(fetPaths_, k == 0, sig.pack_current_A));
          sig.heat_W[static_cast<size_t>(fetNode_[k])] += q;
          sig.fet_heat_W += q;
        }
    }
  }
  sig.ambient_C = in.ambient_C ? *in.ambient_C : ambientFixed_ ? ambient_.value[0] : ambient_.at(t);
}

// The faults' extra heat and internal shorts per cell (HardwareFaults), read once per
// evaluation: no cell's entry past the end of either list (none without faults).
struct Plant::CellFaults {
  const double* heat_W = nullptr;
  size_t heat_cells = 0;
  const double* leak_ohm = nullptr;
  size_t leak_cells = 0;

  explicit CellFaults(const HardwareFaults* f) {
    if (!f) return;
    heat_W = f->cell_heat_W.data();
    heat_cells = f->cell_heat_W.size();
    leak_ohm = f->cell_leak_ohm.data();
    leak_cells = f->cell_leak_ohm.size();
  }
};

namespace {

// A cell's EMF behind R0 and its R0, as cellElectrical stored them.
struct CellEmf {
  double emf_V, r0_ohm;
};

// Cell ci at the state xc, temperature t_C and its group's current i_A (R0's sign): OCV,
// R0 and the EMF behind R0 into sig; returns the last two (a one-cell group's voltage
// from them, not from the signals just stored).
[[gnu::always_inline]] inline CellEmf cellElectrical(const FlatCell& fc, const CellParams& p, size_t ci,
                                                     const double* xc, double t_C, double i_A, PlantSignals& sig) {
  CellHints& h = sig.cell_hints[ci];
  const double soc = xc[CellLayout::soc];
  const double ocv = fc.ocv_V(p, soc, t_C, h);
  sig.cell_ocv_V[ci] = ocv;
  const double r0 = fc.r0_ohm(soc, t_C, i_A, h);
  sig.cell_r0_ohm[ci] = r0;
  const double emf = fc.emf_V(xc, ocv, i_A);
  sig.cell_emf_V[ci] = emf;
  return {emf, r0};
}

// Cell ci's heat at its current (split already): Joule, reversible and hysteresis heat,
// a hot cell's injected heat, an internal short's current and heat.
[[gnu::always_inline]] inline void cellHeat(const FlatCell& fc, const CellParams& p, size_t ci, const double* xc,
                                            double t_C, const Plant::CellFaults& f, PlantSignals& sig) {
  const double i_A = sig.cell_current_A[ci];
  const double rev = fc.reversibleHeat_W(xc[CellLayout::soc], i_A, t_C, sig.cell_hints[ci]);
  sig.cell_reversible_W[ci] = rev;
  double q = fc.heat_W(p, xc, i_A, sig.cell_r0_ohm[ci], rev, t_C);
  sig.internal_A[ci] = 0.0;
  if (ci < f.heat_cells) {
    q += f.heat_W[ci];
    sig.injected_heat_W += f.heat_W[ci];
  }
  if (ci < f.leak_cells && f.leak_ohm[ci] > 0.0) {
    // An internal short: a resistance across the cell's EMF, inside its terminals.
    const double i_int = sig.cell_ocv_V[ci] / f.leak_ohm[ci];
    sig.internal_A[ci] = i_int;
    q += i_int * i_int * f.leak_ohm[ci];
  }
  sig.heat_W[ci] = q;
}

}  // namespace

// Group g at the group current i_A: its cells' OCV, R0 and EMF (curves once per cell),
// the current split, then each cell's heat and its thermal node's temperature. Returns
// the group voltage. Inlined into groupCurrents, its only caller.
template <bool kHeat>
[[gnu::always_inline]] inline double Plant::evaluateGroup(int g, const double* x, double i_A, const CellFaults& f,
                                                         PlantSignals& sig) const {
  const int slot = pack_.layout.size();  // a cell's temperature, after its electrical states
  // One cell a group (most packs read every 10 ms) in one fused pass: the general loops
  // below cost some 480 instructions a tick more on A (12 groups).
  if (pack_.parallel == 1) {  // one cell: it carries the group current (Pack::splitGroup)
    const size_t ci = static_cast<size_t>(g);
    const FlatCell& fc = flat_[ci];
    const CellParams& p = pack_.cells[ci];
    const double* xc = cellStates(x, g);
    const double t_C = fc.temp_C(xc, slot);
    const CellEmf e = cellElectrical(fc, p, ci, xc, t_C, i_A, sig);
    sig.cell_current_A[ci] = i_A;  // Pack::splitGroup's one-cell case, on the values at hand
    const double v = Pack::singleCellVoltage(i_A, e.emf_V, e.r0_ohm);
    if constexpr (kHeat) cellHeat(fc, p, ci, xc, t_C, f, sig);
    sig.node_temp_C[ci] = xc[slot];
    return v;
  }
  const size_t first = static_cast<size_t>(g) * static_cast<size_t>(pack_.parallel);
  const size_t end = first + static_cast<size_t>(pack_.parallel);
  for (size_t ci = first; ci < end; ++ci) {
    const double* xc = cellStates(x, static_cast<int>(ci));
    cellElectrical(flat_[ci], pack_.cells[ci], ci, xc, flat_[ci].temp_C(xc, slot), i_A, sig);
  }
  const double v = pack_.splitGroup(g, i_A, sig.cell_emf_V.data(), sig.cell_r0_ohm.data(), sig.cell_current_A.data());
  for (size_t ci = first; ci < end; ++ci) {
    const double* xc = cellStates(x, static_cast<int>(ci));
    if constexpr (kHeat) cellHeat(flat_[ci], pack_.cells[ci], ci, xc, flat_[ci].temp_C(xc, slot), f, sig);
    sig.node_temp_C[ci] = xc[slot];
  }
  return v;
}

namespace {

// Whether any passive balancing switch is on: a word of eight switches per test.
bool anySwitchOn(const std::vector<uint8_t>& on) {
  const uint8_t* p = on.data();
  const size_t n = on.size();
  uint64_t any = 0;
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    uint64_t w;
    std::memcpy(&w, p + i, sizeof w);
    any |= w;
  }
  if (i + 4 <= n) {  // four more in one word (12 groups: one test instead of four)
    uint32_t w;
    std::memcpy(&w, p + i, sizeof w);
    any |= w;
    i += 4;
  }
  for (; i < n; ++i) any |= p[i];
  return any != 0;
}

}  // namespace

// The plant's balancing hardware picks groupCurrentsWith's variant: a plant without an
// active balancer, and without passive switches or with all of them off (most ticks of
// most runs), runs a loop without their per-group reads and branches (the same
// operations on the values it computes: a converter's current is then 0 and no switch
// is on).
template <bool kHeat>
void Plant::groupCurrents(const double* x, const PlantInputs& in, PlantSignals& sig) const {
  if (busIndex_ >= 0) groupCurrentsWith<kHeat, true, true>(x, in, sig);
  else if (balancer_.present && anySwitchOn(in.balancing)) groupCurrentsWith<kHeat, false, true>(x, in, sig);
  else groupCurrentsWith<kHeat, false, false>(x, in, sig);
}

// Group voltages and cell currents for the string current sig.pack_current_A, with
// each group's balancing resistor (closed form, see the header) and the active
// balancer's converter and precharge currents.
template <bool kHeat, bool kBus, bool kSwitches>
void Plant::groupCurrentsWith(const double* x, const PlantInputs& in, PlantSignals& sig) const {
  auto cellX = [&](int c) { return cellStates(x, c); };
  const double I = sig.pack_current_A;
  const bool bus = kBus;  // busIndex_ >= 0
  sig.pack_voltage_V = -I * pack_.interconnect_ohm;
  sig.balance_heat_W = 0.0;
  sig.bus_V = bus ? x[busIndex_] : 0.0;
  sig.bus_current_A = sig.converter_loss_W = 0.0;
  sig.converter_from_modules_W = sig.converter_to_modules_W = 0.0;

  // Bus precharge from the whole stack: V_stack = A - B·I_pre (linear), so
  // I_pre = (A - V_bus)/(R_pre + B).
  double iPre = 0.0;
  if (bus && in.bus_precharge) {
    double a = 0.0, b = 0.0;
    for (int g = 0; g < pack_.series; ++g) {
      double eg = 0.0, rg = 0.0;
      pack_.groupThevenin(g, cellX, eg, rg, I);
      const double k = balancingFactor(in, g, rg);
      a += k * (eg - rg * (I + converterA(in, static_cast<size_t>(g))));
      b += k * rg;
    }
    iPre = std::max(0.0, (a - sig.bus_V) / (active_.precharge_ohm + b));
  }

  // balancingOn(in, gi) and converterA(in, gi), their lists read once: called per group,
  // they reload each vector after the stores into the signals (the compiler cannot rule
  // out that those alias them): some 150 instructions a tick on A.
  const bool switchable = kSwitches && balancer_.present;
  const uint8_t* switchOn = switchable ? in.balancing.data() : nullptr;
  const size_t switches = switchable ? in.balancing.size() : 0;
  const CellFaults faults(in.faults);
  const size_t parallel = static_cast<size_t>(pack_.parallel);
  const double* converter = in.converter_A.data();
  const size_t converters = bus ? in.converter_A.size() : 0;  // filled with a bus only (hw_balancing)
  // The pack voltage and the balancing heat summed in locals (the same additions in the
  // same order, stored once after the loop), and the per-group outputs through pointers
  // taken once: each store of a cell's value into the signals could be one of these
  // doubles for all the compiler knows, so it reloaded and stored them per group.
  double packV = sig.pack_voltage_V, balanceHeat = sig.balance_heat_W;
  double* groupV = sig.group_voltage_V.data();
  double* cellV = sig.cell_voltage_V.data();
  double* balanceA = sig.balance_current_A.data();
  for (int g = 0; g < pack_.series; ++g) {
    const size_t gi = static_cast<size_t>(g);
    const double ix = gi < converters ? converter[gi] : 0.0;
    const double iString = I + ix + iPre;
    double iBal = 0.0;
    const bool bleeding = gi < switches && switchOn[gi] != 0;
    if (bleeding) {
      double eg = 0.0, rg = 0.0;
      pack_.groupThevenin(g, cellX, eg, rg, iString);
      const double vOn = balancingFactor(in, g, rg) * (eg - rg * iString);
      iBal = balancingDuty(in, gi) * balancer_.current_A(vOn);
    }
    const double v = evaluateGroup<kHeat>(g, x, bleeding ? iString + iBal : iString, faults, sig);
    if (bleeding) balanceHeat += v * iBal;
    groupV[gi] = v;
    packV += v;
    if (parallel == 1) cellV[gi] = v;  // one cell a group: a store, not the loop's set-up
    else for (size_t ci = gi * parallel; ci < (gi + 1) * parallel; ++ci) cellV[ci] = v;
    // With a bus: the module's converter current plus the bus precharge it shares with
    // every module (the record then holds every current the group's cells carry).
    balanceA[gi] = bus ? ix + iPre : iBal;
    if (bus && ix != 0.0) {
      double loss = 0.0;
      sig.bus_current_A += converterBusCurrent_A(active_, v, ix, sig.bus_V, loss);
      sig.converter_loss_W += loss;
      if (ix > 0.0) sig.converter_from_modules_W += v * ix;
      else sig.converter_to_modules_W -= v * ix;
    }
  }
  sig.pack_voltage_V = packV;
  sig.balance_heat_W = balanceHeat;
  if (iPre > 0.0) {
    sig.bus_current_A += iPre;
    sig.converter_loss_W += iPre * iPre * active_.precharge_ohm;
  }
}

[[gnu::always_inline]] inline void Plant::rates(const double* x, double* dx, PlantSignals& sig) const {
  const int slot = pack_.layout.size();
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const size_t ci = static_cast<size_t>(c);
    const double* xc = cellStates(x, c);
    flat_[ci].derivatives(pack_.cells[ci], xc, sig.cell_current_A[ci], dx + c * stride_, sig.internal_A[ci],
                          flat_[ci].temp_C(xc, slot));
  }
  // Thermal network on gathered temperatures; rates scattered to the state slots.
  thermal_.derivatives(sig.node_temp_C.data(), sig.heat_W.data(), sig.ambient_C, coolant_C_,
                       sig.node_rate_K_per_s.data());
  const double* rate = sig.node_rate_K_per_s.data();
  for (size_t j = 0; j < tempState_.size(); ++j) dx[tempState_[j]] = rate[j];
  if (busIndex_ >= 0) dx[busIndex_] = sig.bus_current_A / active_.bus_capacitance_F;
}

// evaluate() and rates() inline, as in derivativesAtCurrent: the fast integrator's one
// evaluation a sub-step, whose nested calls cost more than one cell's arithmetic.
void Plant::derivatives(double t, const double* x, const PlantInputs& in, double* dx, PlantSignals& sig) const {
  currentAtTerminals(t, x, in, sig);
  evaluateAtCurrent<true>(t, x, in, sig);
  rates(x, dx, sig);
}

void Plant::derivativesAtCurrent(double t, const double* x, const PlantInputs& in, double* dx,
                                 PlantSignals& sig) const {
  evaluateAtCurrent<true>(t, x, in, sig);
  rates(x, dx, sig);
}

void Plant::quadratures(const PlantSignals& sig, double* dq) const {
  // Heat from the cells (Joule, and reversible where a cell has dOCV/dT): heat injected
  // by a scripted fault is not drawn from the cells. The chemical energy released is
  // ∫OCV·I, plus the reversible heat -I·T·dOCV/dT where given (the enthalpy), so that
  // chemical = load + heat + stored holds in both cases.
  // FET loss is load-side (inside the energy delivered at the terminals), so not counted here.
  double heat = sig.pack_current_A * sig.pack_current_A * pack_.interconnect_ohm - sig.injected_heat_W -
                sig.fet_heat_W, chem = 0.0;
  for (int j = 0; j < thermal_.nodeCount(); ++j) heat += sig.heat_W[static_cast<size_t>(j)];
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const size_t ci = static_cast<size_t>(c);
    chem += sig.cell_ocv_V[ci] * (sig.cell_current_A[ci] + sig.internal_A[ci]);
    if (flat_[ci].has_entropic) chem += sig.cell_reversible_W[ci];  // as evaluated with the heat
  }
  // Balancing heat sits in the board node's heat_W when there is one.
  if (boardNode_ < 0) heat += sig.balance_heat_W;
  heat += sig.converter_loss_W;
  double balanceCharge = 0.0;
  if (balancer_.present)
    for (double i : sig.balance_current_A) balanceCharge += i;
  dq[kQuadCharge_As] = sig.pack_current_A;
  dq[kQuadLoadEnergy_J] = sig.pack_current_A * sig.pack_voltage_V;
  dq[kQuadHeat_J] = heat;
  dq[kQuadChemEnergy_J] = chem;
  dq[kQuadBalanceCharge_As] = balanceCharge;
  dq[kQuadBalanceHeat_J] = sig.balance_heat_W;
  dq[kQuadConverterFromModules_J] = sig.converter_from_modules_W;
  dq[kQuadConverterToModules_J] = sig.converter_to_modules_W;
}

std::vector<Plant::RcBranch> Plant::rcBranches() const {
  std::vector<RcBranch> b;
  for (int c = 0; c < pack_.cellCount(); ++c) {
    const CellParams& p = pack_.cells[static_cast<size_t>(c)];
    for (int k = 0; k < pack_.layout.n_rc; ++k)
      b.push_back({c * stride_ + pack_.layout.rc(k), p.rc[static_cast<size_t>(k)].tau_s(), c, k,
                   p.rc[static_cast<size_t>(k)].variable});
    if (pack_.layout.hysteresis) b.push_back({c * stride_ + pack_.layout.hyst(), INFINITY, c, -1, true, true});
  }
  return b;
}

double Plant::rcTau_s(const double* x, const PlantSignals& sig, const RcBranch& b) const {
  const CellParams& p = pack_.cells[static_cast<size_t>(b.cell)];
  if (!b.variable) return b.tau_s;
  if (b.hysteresis) {  // dh/dt = k·(target - h), k = γ·|i|/3600
    const double k = p.hysteresis_rate_per_Ah * std::fabs(sig.cell_current_A[static_cast<size_t>(b.cell)]) / 3600.0;
    return k > 0.0 ? 1.0 / k : INFINITY;
  }
  const double* xc = cellStates(x, b.cell);
  const double t_C = pack_.cellTemp_C(b.cell, xc);
  const RcPair& rc = p.rc[static_cast<size_t>(b.pair)];
  return ecm::rcR_ohm(rc, p, xc[CellLayout::soc], t_C) * ecm::rcC_F(rc, p, xc[CellLayout::soc], t_C);
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
    // A cell whose curves depend on temperature is bounded over the cell
    // temperatures a run can see (kOperatingTemps_C); the others at one temperature.
    static constexpr double kOperatingTemps_C[] = {-40.0, -20.0, 0.0, 25.0, 45.0, 60.0, 80.0};
    for (const CellParams& p : pack_.cells) {
      const bool hot = p.usesTemperature();
      for (const double t_C : kOperatingTemps_C) {
        if (!hot && t_C != kReferenceTemp_C) continue;
        double r0_min = INFINITY, slope_max = 0.0, prev = ecm::ocv(p, 0.0, t_C), c_min = INFINITY;
        for (int i = 0; i <= kGrid; ++i) {
          const double soc = static_cast<double>(i) / kGrid;
          r0_min = std::min({r0_min, ecm::r0(p, soc, t_C, 1.0), ecm::r0(p, soc, t_C, -1.0)});
          for (const RcPair& rc : p.rc) c_min = std::min(c_min, ecm::rcC_F(rc, p, soc, t_C));
          if (i > 0) {
            const double v = ecm::ocv(p, soc, t_C);
            slope_max = std::max(slope_max, std::fabs(v - prev) * kGrid);
            prev = v;
          }
        }
        if (!(r0_min > 0.0)) continue;
        if (slope_max > 0.0) tau = std::min(tau, 3600.0 * p.capacity_Ah * r0_min / slope_max);
        if (!p.rc.empty()) tau = std::min(tau, c_min * r0_min);
        if (p.has_hysteresis) {
          // h moves the cell's EMF, hence its share of the group current, hence dh/dt:
          // rate γ·(M + h)/(3600·R0) <= γ·2·M_max/(3600·R0).
          double m_max = 0.0;
          for (int i = 0; i <= kGrid; ++i)
            m_max = std::max(m_max, p.hysteresis_max_V.eval(static_cast<double>(i) / kGrid, p.axisCapacity_Ah(), t_C));
          if (m_max > 0.0) tau = std::min(tau, 3600.0 * r0_min / (p.hysteresis_rate_per_Ah * 2.0 * m_max));
        }
      }
    }
  }
  if (busIndex_ >= 0) {
    // Bus: precharge R·C; converters dI_bus/dV_bus = -P/V² gives C·V²/P at the lowest
    // bus voltage they run at.
    const ActiveBalancerConfig& a = active_;
    tau = std::min(tau, a.precharge_ohm * a.bus_capacitance_F);
    const double p_max_W =
        2.0 * a.converter_current_A * a.module_max_V / a.efficiencyAt(a.converter_current_A, a.module_min_V);
    const double v = std::max(a.precharge_below_V, 0.1);
    tau = std::min(tau, a.bus_capacitance_F * v * v / p_max_W);
  }
  return tau;
}

}  // namespace packsim
