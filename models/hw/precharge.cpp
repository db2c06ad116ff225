#include "models/hw/precharge.hpp"

#include <cmath>

namespace packsim {

double prechargeStep(const PrechargePathConfig& c, double pack_V, double& bus_V, double dt_s) {
  const bool leak = c.bus_leak_ohm > 0.0;
  const double rl = c.bus_leak_ohm;
  const double vinf = leak ? pack_V * rl / (c.r_ohm + rl) : pack_V;
  const double rpar = leak ? c.r_ohm * rl / (c.r_ohm + rl) : c.r_ohm;
  const double tau = c.bus_capacitance_F * rpar;
  const double v0 = bus_V;
  const double decay = tau > 0.0 ? std::exp(-dt_s / tau) : 0.0;
  bus_V = vinf + (v0 - vinf) * decay;
  const double integral = vinf * dt_s + (v0 - vinf) * tau * (1.0 - decay);
  return dt_s > 0.0 ? (pack_V * dt_s - integral) / (c.r_ohm * dt_s) : 0.0;
}

void busIdleStep(const PrechargePathConfig& c, double& bus_V, double dt_s) {
  if (c.bus_leak_ohm <= 0.0) return;
  bus_V *= std::exp(-dt_s / (c.bus_leak_ohm * c.bus_capacitance_F));
}

}  // namespace packsim
