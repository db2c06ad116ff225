// The plant as one ODE: the pack's cells (electrical states from the ECM) and the
// thermal network's nodes, under the inputs the actuators, the load and the injected
// faults hold fixed between discontinuities.
//
//   state layout  cell i: [soc, v_rc_1 … v_rc_K, (h), T]  at i·stride   (stride = K + 2,
//                 + 1 with hysteresis)
//                 extra thermal nodes (board, FETs, …) after the cells
//   quadratures   [charge out (A·s), energy to load (J), heat (J), chemical energy (J),
//                  balancing charge (A·s), balancing heat (J), converter energy from /
//                  to the modules (J)]
//   pack current  I = relay_closed ? load(t) + extra - I_charger : 0   (positive discharges)
//                 a power load P solves V(I)·I = P with V(I) = E - R·I (pack Thevenin)
//                 a CC-CV charger gives I_chg = clamp((V_set - E)/R, 0, I_lim)
//   balancing     group g carries I + I_conv,g (+ I_pre) through the string; with its
//                 balancing switch on, V_g = k·(E_g - R_g·I_string), k = 1/(1 + R_g/R_bal)
//                 and I_bal = V_g/R_bal is drawn on top (models/balance/passive_balancer);
//                 its heat V_g·I_bal goes into the board node
//   active bal.   one extra state, the supercap bus voltage (models/balance/active_balancer);
//                 I_pre = (V_stack - V_bus)/R_pre while precharging, drawn from every group
//
// Jacobian (jacobianPattern, core/sim/plant_pattern.cpp): a cell's states couple to
// every state of its parallel group (the current split), its temperature to its thermal
// neighbours; that is all for a current load. The extra states (thermal nodes, bus) are
// loose rows: a node's dependence on the cells' states is left out (see sparsity.hpp).
#pragma once
#include <algorithm>
#include <optional>
#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/hardware_faults.hpp"
#include "core/sim/sparsity.hpp"
#include "models/cell/flat_cell.hpp"
#include "models/load/load_profile.hpp"
#include "models/pack/pack.hpp"
#include "models/thermal/thermal_network.hpp"

namespace packsim {

struct PlantInputs {
  bool relay_closed = false;
  LoadSegment load;
  const HardwareFaults* faults = nullptr;  // extra load, hot-cell heat, internal shorts
  // Switching hardware (core/sim/bms_bridge): with the main path open the pack only
  // feeds the precharge path; a FET that is off (and its diode) blocks one direction.
  double precharge_A = 0.0;
  bool discharge_blocked = false;
  bool charge_blocked = false;
  bool discharge_fet_on = false;  // gates as driven (their I²·Rds_on heats a FET node)
  bool charge_fet_on = false;
  // Balancing and charging (issue 5), per series group where a vector.
  std::vector<uint8_t> balancing;   // passive balancing switch actually on
  std::vector<double> balance_duty; // share of the time a switch that is on conducts (the monitor IC opens
                                    // it for conversions): its average current; empty = 1
  std::vector<double> bias_A;       // monitor ICs' thermistor bias drawn from a group (A; empty: none)
  std::vector<double> converter_A;  // active balancer module-side current (+ into the bus): only with one
  bool bus_precharge = false;       // active balancer bus charging from the stack
  double charger_limit_A = 0.0;     // CC-CV charger on with this current limit; 0 = off
  double charger_setpoint_V = 0.0;
  std::optional<double> ambient_C;  // set: replaces the scenario's ambient profile (an FMU's input)
};

// Everything the plant derives from a state at a time, reused between calls.
struct PlantSignals {
  std::vector<double> cell_current_A;
  std::vector<double> cell_voltage_V;   // terminal voltage (= its group's voltage)
  std::vector<double> group_voltage_V;
  std::vector<double> heat_W;           // per thermal node (not by Plant::sample, nor the fields marked *)
  std::vector<double> node_temp_C;
  std::vector<double> node_rate_K_per_s;
  std::vector<double> internal_A;       // * current through an internal short, per cell
  std::vector<double> cell_ocv_V;       // OCV and R0 at the cell's SOC (curves evaluated once)
  std::vector<double> cell_r0_ohm;
  std::vector<double> cell_emf_V;       // behind R0: OCV - Σ v_rc (+ h - M0·sgn i): the current split's input
  std::vector<double> cell_reversible_W;  // * -i·T_K·dOCV/dT (0 without): heat, and again the chemical energy
  std::vector<CellHints> cell_hints;    // each cell's table segments found last time (speed only)
  double pack_current_A = 0.0;
  double pack_voltage_V = 0.0;
  double ambient_C = 25.0;
  double injected_heat_W = 0.0;  // * heat from scripted faults (hot cell), not Joule heat
  double fet_heat_W = 0.0;       // * FET loss in a FET node: outside the pack terminals (load side)
  std::vector<double> balance_current_A;  // per group: passive I_bal, or converter module current + bus precharge
  double balance_heat_W = 0.0;            // passive balancing resistors + FETs
  double charger_A = 0.0;                 // into the pack
  double bus_V = 0.0;                     // active balancer supercap bus
  double bus_current_A = 0.0;             // into the bus (converters + precharge)
  double converter_loss_W = 0.0;          // converters + precharge resistor
  double converter_from_modules_W = 0.0;  // Σ V_g·I_conv,g over converters drawing from modules (not precharge)
  double converter_to_modules_W = 0.0;    // Σ V_g·|I_conv,g| over converters feeding modules
};

enum Quadrature {
  kQuadCharge_As = 0, kQuadLoadEnergy_J, kQuadHeat_J, kQuadChemEnergy_J,
  kQuadBalanceCharge_As, kQuadBalanceHeat_J, kQuadConverterFromModules_J, kQuadConverterToModules_J,
  kQuadCount
};

class Plant {
 public:
  explicit Plant(const Scenario& s);

  const Pack& pack() const { return pack_; }
  const ThermalNetwork& thermal() const { return thermal_; }
  int stateSize() const { return stateSize_; }
  // Sparsity of d(derivatives)/dx, followed by `quadratures` loose states nothing reads.
  JacobianPattern jacobianPattern(int quadratures) const;
  int stride() const { return stride_; }
  // The active balancer's bus voltage (-1 without one).
  int busIndex() const { return busIndex_; }
  // State index of thermal node j (cells first, then extra nodes). Inline: read per cell
  // and tick by the loop and the recorder.
  int tempIndex(int node) const {
    const int cells = pack_.cellCount();
    return node < cells ? node * stride_ + pack_.layout.size() : cells * stride_ + (node - cells);
  }
  const double* cellStates(const double* x, int cell) const { return x + cell * stride_; }
  const std::vector<double>& initialSoc() const { return initialSoc_; }
  // A FET's thermal node (-1 if none): its I²·Rds_on (or diode) loss heats it.
  int fetNode() const { return std::max(fetNode_[0], fetNode_[1]); }
  // The balancing board's thermal node (-1 if none): the first board's.
  int boardNode() const { return boardNode_; }
  // Monitor boards (hardware.balancing.cells_per_board): board b's thermal node, -1 if none.
  int boardCount() const { return static_cast<int>(boardNodes_.size()); }
  int boardNodeOf(int board) const { return boardNodes_.empty() ? -1 : boardNodes_[static_cast<size_t>(board)]; }
  // Thermal node of the board series group g's resistor sits on (-1 if none).
  int boardNodeOfGroup(int g) const { return boardNodeOf(balancer_.boardOf(g)); }

  void initialState(double* x) const;
  // Algebraic part: currents, voltages, heat, temperatures at (t, x).
  void evaluate(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const;
  // evaluate() for a reader of the signals that needs no heat (the loop's sample at a
  // tick: sensors, recorder, fault scheduler, switchgear): the same values, except that
  // the heat and leaks only rates() and quadratures() read (heat_W, cell_reversible_W,
  // internal_A, injected_heat_W, fet_heat_W) keep whatever they held. It skips the
  // per-cell heat (a curve and a few multiplies per cell) and the nodes' heat.
  void sample(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const;
  void derivatives(double t, const double* x, const PlantInputs& in, double* dx, PlantSignals& sig) const;
  // The two halves of evaluate(): the current at the pack's terminals (sig.pack_current_A,
  // sig.charger_A: under a power load or a charger it depends on every cell), then
  // everything else for that current. derivativesAtCurrent takes the current already in
  // sig (from terminalCurrent at another state: the Jacobian holds it, plant_ode.hpp).
  void terminalCurrent(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const;
  // The pack seen from its terminals at state x: V = E - R·I (what a power load solves on).
  void thevenin(const double* x, const PlantInputs& in, double& e_V, double& r_ohm) const;
  void derivativesAtCurrent(double t, const double* x, const PlantInputs& in, double* dx, PlantSignals& sig) const;
  // Rates of the quadratures from signals already evaluated at (t, x) (by evaluate/derivatives):
  // they hold all it reads, the reversible heat too.
  void quadratures(const PlantSignals& sig, double* dq) const;
  PlantSignals makeSignals() const;

  // For integrators that update RC branches in closed form (core/sim/fast_integrator):
  // branch k obeys dv/dt = (i·R - v)/τ, with its rate given by derivatives().
  struct RcBranch {
    int state = 0;     // index in the state vector
    double tau_s = 0;  // R·C of the branch (a constant pair)
    int cell = 0, pair = 0;
    bool variable = false;    // R or C depends on SOC / temperature: see rcTau_s
    bool hysteresis = false;  // the cell's hysteresis state: dh/dt = (target - h)/τ, τ = 3600/(γ·|i|)
  };
  std::vector<RcBranch> rcBranches() const;
  // τ of a branch at the state x with the signals evaluated there (its constant tau_s
  // unless it is variable; infinite for a hysteresis state without current).
  double rcTau_s(const double* x, const PlantSignals& sig, const RcBranch& b) const;
  // Smallest time constant (s) of the states an explicit update advances (everything
  // but the RC branches' own decay): thermal nodes, and within parallel groups the
  // current split's feedback on SOC and RC voltages. A state added to the plant adds
  // its time constant here, so fixed-step integrators stay stable.
  double explicitTimeConstant_s() const;

  // The faults' heat and leaks per cell, as the per-cell loop reads them (plant.cpp).
  struct CellFaults;

 private:
  double packCurrent(double t, const PlantInputs& in, double e_V, double r_ohm) const;
  // terminalCurrent's body, inlined into evaluate() and sample(): for the usual current
  // load the call cost about as much as the work (plant.cpp).
  void currentAtTerminals(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const;
  // Pack Thevenin seen from the terminals with the held balancing / converter currents.
  template <typename CellX>
  void packThevenin(const PlantInputs& in, CellX cellX, double& e_V, double& r_ohm) const;
  bool balancingOn(const PlantInputs& in, size_t gi) const;  // group gi's passive switch is on
  double balancingDuty(const PlantInputs& in, size_t gi) const;  // PlantInputs::balance_duty (1 if unset)
  double balancingFactor(const PlantInputs& in, int g, double r_g) const;
  // kHeat = false: without the heat (sample()) in these three.
  template <bool kHeat>
  void groupCurrents(const double* x, const PlantInputs& in, PlantSignals& sig) const;
  // groupCurrents for a plant with (kBus) or without the active balancer's bus, and with
  // (kSwitches: when balancer_.present) or without passive balancing switches.
  template <bool kHeat, bool kBus, bool kSwitches>
  void groupCurrentsWith(const double* x, const PlantInputs& in, PlantSignals& sig) const;
  // Group g at the group current i_A: its cells' OCV, R0, EMF, currents, heat and
  // temperatures into sig (curves once per cell); returns the group voltage.
  template <bool kHeat>
  double evaluateGroup(int g, const double* x, double i_A, const CellFaults& f, PlantSignals& sig) const;
  // Always inlined (plant.cpp; said here, where GCC takes it for every call).
  template <bool kHeat>
  [[gnu::always_inline]] void evaluateAtCurrent(double t, const double* x, const PlantInputs& in,
                                                PlantSignals& sig) const;
  void rates(const double* x, double* dx, PlantSignals& sig) const;  // from evaluated signals

  Pack pack_;
  ThermalNetwork thermal_;
  TimeSeries ambient_;
  bool ambientFixed_ = false;  // one point: ambient_.at(t) is its value at every t
  double coolant_C_ = 25.0;
  LoadProfile::Quantity loadQuantity_ = LoadProfile::Quantity::Current_A;
  std::vector<double> initialSoc_;
  int stride_ = 0;
  int stateSize_ = 0;
  double initialTemp_C_ = 25.0;
  PassiveBalancerConfig balancer_;
  ActiveBalancerConfig active_;
  int boardNode_ = -1;
  int fetNode_[2] = {-1, -1};     // discharge FET, charge FET
  bool fetHeats_ = false;         // either FET has a thermal node
  MosfetConfig fet_[2];
  FetPaths fetPaths_ = FetPaths::Series;
  std::vector<int> boardNodes_;  // per monitor board; empty without a board node
  std::vector<std::pair<int, double>> externalHeat_W_;  // (node, W): heat from outside the pack
  int busIndex_ = -1;
  // Per cell: its curves and constants laid out for the per-cell loop (pointing into
  // pack_'s curves, whose arrays every copy shares).
  std::vector<FlatCell> flat_;
  std::vector<int> tempState_;  // tempIndex(j) per thermal node, for rates()' scatter
};

}  // namespace packsim
