// Active balancer (reference system B): one isolated bidirectional DC/DC converter per
// module (series group), all exchanging energy with a shared supercapacitor bus.
//
//   converter k   module-side current I_k (+ draws from the module, - feeds it),
//                 |I_k| = converter_current_A while on; bus-side current
//                   module -> bus:  I_bus = η·V_k·I_k / V_bus
//                   bus -> module:  I_bus = V_k·I_k / (η·V_bus)            (I_k < 0)
//                 loss = |V_k·I_k - V_bus·I_bus|
//                 η from a table over |I_k| (`efficiency`), or from a loss model of
//                 the converter (`losses`): P_loss = P_fixed + R_eq·I_k² on the module
//                 side's power V_k·|I_k| (η = 1 - P_loss / (V_k·|I_k|), at least 0.01)
//   bus           C·dV_bus/dt = Σ_k I_bus,k + I_pre
//   precharge     while V_bus < precharge_below_V the bus charges from the whole stack
//                 through precharge_ohm (inrush V_stack/R) and every converter is off
//   controller    every tick, from the module voltages the BMS reports (CAN):
//                 safe state (the BMS isolated the pack, or any module > module_max_V
//                 or < module_min_V): all off, the precharge too;
//                 else the highest module -> bus unless the bus is above bus_high_V,
//                 and bus -> the lowest module unless the bus is below bus_low_V;
//                 nothing while max - min <= deadband_V
// Units: V, A, F, Ω.
#pragma once
#include <vector>

namespace packsim {

struct ActiveBalancerConfig {
  bool present = false;
  double converter_current_A = 3.0;
  std::vector<double> efficiency_at_A{0.0};  // table: module-side current (A) ...
  std::vector<double> efficiency{0.85};      // ... -> efficiency (0..1]; one entry: constant
  double bus_capacitance_F = 100.0;
  double bus_initial_V = 0.0;
  double bus_rated_V = 5.0;
  double precharge_ohm = 2.2;
  double precharge_below_V = 2.0;
  double bus_low_V = 2.5;
  double bus_high_V = 4.5;
  double module_min_V = 2.5;
  double module_max_V = 4.2;
  double deadband_V = 0.01;
  bool loss_model = false;      // losses: instead of the efficiency table
  double loss_fixed_W = 0.0;    // controller, gate drive, core: while a converter runs
  double loss_series_ohm = 0.0; // conduction (FETs, windings) referred to the module-side current

  // η of one converter at module-side current |I| and module voltage V.
  double efficiencyAt(double current_A, double module_V) const;
};

struct ActiveBalancerCommand {
  int source = -1;   // module discharged into the bus
  int sink = -1;     // module charged from the bus
  bool precharge = false;
  bool safe_state = false;  // every converter and the precharge off
  bool isolated = false;    // ... because the BMS isolated the pack
};

// packIsolated: the BMS has isolated the pack on an unsafe condition (its error state).
ActiveBalancerCommand activeBalancerDecide(const ActiveBalancerConfig& c, const std::vector<double>& module_V,
                                           double bus_V, bool packIsolated = false);

// Bus-side current (A, + into the bus) and loss (W) of one converter.
double converterBusCurrent_A(const ActiveBalancerConfig& c, double module_V, double module_A, double bus_V,
                             double& loss_W);

}  // namespace packsim
