// The plant as one ODE: the pack's cells (electrical states from the ECM) and the
// thermal network's nodes, under the inputs the actuators and the load hold fixed
// between discontinuities.
//
//   state layout  cell i: [soc, v_rc_1 … v_rc_K, T]  at i·stride   (stride = K + 2)
//                 extra thermal nodes (none yet) after the cells
//   quadratures   [charge out (A·s), energy to load (J), heat (J), chemical energy (J)]
//   pack current  I = relay_closed ? load(t) : 0     (positive discharges)
//
// Cells are stored group by group, so every coupling (parallel current split,
// neighbour conductance) sits within a band of about one group's width: the Jacobian
// is block-banded, never dense.
#pragma once
#include <vector>

#include "core/scenario/scenario.hpp"
#include "models/load/load_profile.hpp"
#include "models/pack/pack.hpp"
#include "models/thermal/thermal_network.hpp"

namespace packsim {

struct PlantInputs {
  bool relay_closed = false;
  LoadSegment load;
  double ambient_C = 25.0;
};

// Everything the plant derives from a state at a time, reused between calls.
struct PlantSignals {
  std::vector<double> cell_current_A;
  std::vector<double> cell_voltage_V;   // terminal voltage (= its group's voltage)
  std::vector<double> group_voltage_V;
  std::vector<double> heat_W;           // per thermal node
  std::vector<double> node_temp_C;
  std::vector<double> node_rate_K_per_s;
  double pack_current_A = 0.0;
  double pack_voltage_V = 0.0;
};

enum Quadrature { kQuadCharge_As = 0, kQuadLoadEnergy_J, kQuadHeat_J, kQuadChemEnergy_J, kQuadCount };

class Plant {
 public:
  explicit Plant(const Scenario& s);

  const Pack& pack() const { return pack_; }
  const ThermalNetwork& thermal() const { return thermal_; }
  int stateSize() const { return stateSize_; }
  int bandwidth() const;  // upper = lower half-bandwidth of the Jacobian
  int stride() const { return stride_; }
  int tempIndex(int cell) const { return cell * stride_ + pack_.layout.size(); }
  const double* cellStates(const double* x, int cell) const { return x + cell * stride_; }

  void initialState(double* x) const;
  // Algebraic part: currents, voltages, heat, temperatures at (t, x).
  void evaluate(double t, const double* x, const PlantInputs& in, PlantSignals& sig) const;
  void derivatives(double t, const double* x, const PlantInputs& in, double* dx, PlantSignals& sig) const;
  void quadratures(double t, const double* x, const PlantInputs& in, double* dq, PlantSignals& sig) const;
  PlantSignals makeSignals() const;

 private:
  Pack pack_;
  ThermalNetwork thermal_;
  int stride_ = 0;
  int stateSize_ = 0;
  double initialSoc_ = 1.0;
  double initialTemp_C_ = 25.0;
};

}  // namespace packsim
