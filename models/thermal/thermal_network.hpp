// Lumped thermal network: nodes with heat capacity, conductances between nodes and
// from each node to ambient.
//
//   C_i · dT_i/dt = q_i - G_amb,i·(T_i - T_amb) - G_cool,i·(T_i - T_cool)
//                   - Σ_j G_ij·(T_i - T_j)
//
// Units: J/K, W/K, W, °C. Nodes 0…n_cells-1 are the cells; further named nodes
// (balancing board, FETs, enclosure) follow. Ambient and coolant are boundaries at a
// given temperature. Steady state of a single node: T = T_amb + q/G_amb.
#pragma once
#include <string>
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
  std::vector<double> g_coolant_W_per_K;      // per node
  std::vector<std::string> name;              // per node ("cell 3", "board", …)
  std::vector<ThermalLink> links;

  int nodeCount() const { return static_cast<int>(heat_capacity_J_per_K.size()); }
  int addNode(const std::string& name, double heat_capacity_J_per_K, double g_ambient_W_per_K,
              double g_coolant_W_per_K = 0.0);
  int find(const std::string& name) const;  // -1 if absent
  void link(int a, int b, double g_W_per_K);
  // dT[i] from node temperatures T, heat inputs q and the boundary temperatures.
  void derivatives(const double* T_C, const double* q_W, double ambient_C, double coolant_C, double* dT) const;
};

}  // namespace packsim
