#include "models/thermal/thermal_network.hpp"

#include <stdexcept>

namespace packsim {

int ThermalNetwork::addNode(const std::string& n, double c, double g, double g_cool) {
  if (!(c > 0.0)) throw std::invalid_argument("thermal node heat capacity must be > 0");
  if (!(g >= 0.0) || !(g_cool >= 0.0)) throw std::invalid_argument("thermal node conductance must be >= 0");
  heat_capacity_J_per_K.push_back(c);
  g_ambient_W_per_K.push_back(g);
  g_coolant_W_per_K.push_back(g_cool);
  name.push_back(n);
  return nodeCount() - 1;
}

int ThermalNetwork::find(const std::string& n) const {
  for (int i = 0; i < nodeCount(); ++i)
    if (name[static_cast<size_t>(i)] == n) return i;
  return -1;
}

void ThermalNetwork::link(int a, int b, double g) {
  if (a < 0 || b < 0 || a >= nodeCount() || b >= nodeCount() || a == b)
    throw std::invalid_argument("thermal link between invalid nodes");
  links.push_back({a, b, g});
}

void ThermalNetwork::derivatives(const double* T, const double* q, double ambient_C, double coolant_C,
                                 double* dT) const {
  const int n = nodeCount();
  for (int i = 0; i < n; ++i) {
    const size_t k = static_cast<size_t>(i);
    dT[i] = q[i] - g_ambient_W_per_K[k] * (T[i] - ambient_C) - g_coolant_W_per_K[k] * (T[i] - coolant_C);
  }
  for (const ThermalLink& l : links) {
    const double flow_W = l.g_W_per_K * (T[l.a] - T[l.b]);
    dT[l.a] -= flow_W;
    dT[l.b] += flow_W;
  }
  for (int i = 0; i < n; ++i) dT[i] /= heat_capacity_J_per_K[i];
}

}  // namespace packsim
