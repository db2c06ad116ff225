#include "models/balance/active_balancer.hpp"

#include <algorithm>
#include <cmath>

#include "models/cell/curve.hpp"

namespace packsim {

double ActiveBalancerConfig::efficiencyAt(double current_A, double module_V) const {
  if (!loss_model) return interpolate(efficiency_at_A, efficiency, current_A);
  const double p_W = module_V * current_A;
  if (!(p_W > 0.0)) return 0.01;
  return std::max(0.01, 1.0 - (loss_fixed_W + loss_series_ohm * current_A * current_A) / p_W);
}

ActiveBalancerCommand activeBalancerDecide(const ActiveBalancerConfig& c, const std::vector<double>& module_V,
                                           double bus_V, bool packIsolated) {
  ActiveBalancerCommand cmd;
  if (!c.present || module_V.empty()) return cmd;
  if (packIsolated) {
    cmd.safe_state = cmd.isolated = true;
    return cmd;
  }
  int hi = 0, lo = 0;
  for (int k = 0; k < static_cast<int>(module_V.size()); ++k) {
    const double v = module_V[static_cast<size_t>(k)];
    if (v > c.module_max_V || v < c.module_min_V) cmd.safe_state = true;
    if (v > module_V[static_cast<size_t>(hi)]) hi = k;
    if (v < module_V[static_cast<size_t>(lo)]) lo = k;
  }
  if (cmd.safe_state) return cmd;
  if (bus_V < c.precharge_below_V) {
    cmd.precharge = true;
    return cmd;
  }
  if (module_V[static_cast<size_t>(hi)] - module_V[static_cast<size_t>(lo)] <= c.deadband_V) return cmd;
  if (bus_V < c.bus_high_V) cmd.source = hi;
  if (bus_V > c.bus_low_V) cmd.sink = lo;
  return cmd;
}

double converterBusCurrent_A(const ActiveBalancerConfig& c, double module_V, double module_A, double bus_V,
                             double& loss_W) {
  loss_W = 0.0;
  if (module_A == 0.0 || !(bus_V > 0.0)) return 0.0;
  const double eta = c.efficiencyAt(std::fabs(module_A), module_V);
  const double p_module_W = module_V * module_A;  // + leaves the module
  const double p_bus_W = module_A > 0.0 ? eta * p_module_W : p_module_W / eta;
  loss_W = std::fabs(p_module_W - p_bus_W);
  return p_bus_W / bus_V;
}

}  // namespace packsim
