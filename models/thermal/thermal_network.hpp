// Lumped thermal network: nodes with heat capacity, conductances between nodes and
// from each node to ambient.
//
//   C_i · dT_i/dt = q_i - G_amb,i·(T_i - T_amb) - Σ_j G_ij·(T_i - T_j)
//
// Units: J/K, W/K, W, °C. Nodes 0…n_cells-1 are the cells; further nodes (balancing
// board, FETs, enclosure) follow. Steady state of a single node: T = T_amb + q/G_amb.
#pragma once
#include <vector>

namespace packsim {

struct ThermalLink {
  int a = 0;
  int b = 0;
  double g_W_per_K = 0.0;
};

struct ThermalNetwork {
  std::vector<double> heat_capacity_J_per_K;  // per node
  std::vector<double> g_ambient_W_per_K;      // per node
  std::vector<ThermalLink> links;

  int nodeCount() const { return static_cast<int>(heat_capacity_J_per_K.size()); }
  int addNode(double heat_capacity_J_per_K, double g_ambient_W_per_K);
  void link(int a, int b, double g_W_per_K);
  // dT[i] from node temperatures T, heat inputs q and the ambient temperature.
  void derivatives(const double* T_C, const double* q_W, double ambient_C, double* dT) const;
};

}  // namespace packsim
