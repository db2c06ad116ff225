// Precharge resistor into the load-bus capacitance, with an optional resistance
// across the bus (bleeder, or a shorted load). Over one tick the pack voltage is
// frozen and the RC is solved exactly:
//
//   V_inf = V_pack · R_L / (R_pre + R_L),   τ = C · (R_pre ∥ R_L)
//   v(t+dt) = V_inf + (v - V_inf) · e^(-dt/τ)
//   mean pack current over the tick = (V_pack·dt - ∫v dt) / R_pre
//
// With the main path closed the bus follows the pack; with everything open the bus
// decays through R_L alone (τ = R_L·C).
#pragma once

namespace packsim {

struct PrechargePathConfig {
  double r_ohm = 100.0;
  double bus_capacitance_F = 1e-3;
  double bus_leak_ohm = 0.0;  // 0 = none (infinite)
};

// One tick of the precharge path. Returns the mean current drawn from the pack
// (positive = discharge) and updates bus_V.
double prechargeStep(const PrechargePathConfig& c, double pack_V, double& bus_V, double dt_s);
// Bus with nothing connected: decays through the leak (if any).
void busIdleStep(const PrechargePathConfig& c, double& bus_V, double dt_s);

}  // namespace packsim
