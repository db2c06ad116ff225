#include "models/thermal/thermal_network.hpp"

#include <stdexcept>

namespace packsim {

int ThermalNetwork::addNode(double c, double g) {
  if (!(c > 0.0)) throw std::invalid_argument("thermal node heat capacity must be > 0");
  if (!(g >= 0.0)) throw std::invalid_argument("thermal node ambient conductance must be >= 0");
  heat_capacity_J_per_K.push_back(c);
  g_ambient_W_per_K.push_back(g);
  return nodeCount() - 1;
}

void ThermalNetwork::link(int a, int b, double g) {
  if (a < 0 || b < 0 || a >= nodeCount() || b >= nodeCount() || a == b)
    throw std::invalid_argument("thermal link between invalid nodes");
  links.push_back({a, b, g});
}

void ThermalNetwork::derivatives(const double* T, const double* q, double ambient_C, double* dT) const {
  const int n = nodeCount();
  for (int i = 0; i < n; ++i) dT[i] = q[i] - g_ambient_W_per_K[i] * (T[i] - ambient_C);
  for (const ThermalLink& l : links) {
    const double flow_W = l.g_W_per_K * (T[l.a] - T[l.b]);
    dT[l.a] -= flow_W;
    dT[l.b] += flow_W;
  }
  for (int i = 0; i < n; ++i) dT[i] /= heat_capacity_J_per_K[i];
}

}  // namespace packsim
