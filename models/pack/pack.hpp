// Pack topology: Ns series groups of Mp parallel cells (cell index = group·Mp + p).
//
// Cells of one group share the group terminal voltage V_g and split the group
// current I_g by their EMF E_i (OCV minus RC polarisation) and series resistance R0_i:
//
//   I_i = (E_i - V_g) / R0_i,   V_g = (Σ E_i/R0_i - I_g) / Σ 1/R0_i
//
// which conserves Σ I_i = I_g exactly. Seen from the terminals a group is a Thevenin
// source E_g = Σ(E_i/R0_i)/Σ(1/R0_i) behind R_g = 1/Σ(1/R0_i), so the pack is
// V = Σ E_g - I·(Σ R_g + R_interconnect): linear in I, which makes a constant-power
// load solvable in closed form. Positive current discharges.
//
// A cell whose curves depend on temperature reads its temperature from the slot after
// its electrical states (x_cell(i)[layout.size()], as the plant stores it); R0 is the
// charge R0 when the group current is negative (a parallel cell is taken to carry the
// sign of its group's current).
#pragma once
#include <cstdint>
#include <vector>

#include "models/cell/ecm.hpp"

namespace packsim {

struct Pack {
  int series = 1;
  int parallel = 1;
  std::vector<CellParams> cells;  // series·parallel entries
  CellLayout layout;              // shared by every cell (same number of RC pairs)
  double interconnect_ohm = 0.0;  // total busbar/interconnect resistance in the current path
  // Per cell: whether its curves read the temperature (CellParams::usesTemperature),
  // worked out once by cacheTemperatureUse(); empty: asked of the cell each time.
  std::vector<uint8_t> uses_temp;

  void cacheTemperatureUse() {
    uses_temp.resize(cells.size());
    for (size_t i = 0; i < cells.size(); ++i) uses_temp[i] = cells[i].usesTemperature() ? 1 : 0;
  }

  int cellCount() const { return series * parallel; }
  // Temperature of cell i for its curves (kReferenceTemp_C if none depends on it).
  double cellTemp_C(int i, const double* x) const {
    const size_t ci = static_cast<size_t>(i);
    const bool uses = ci < uses_temp.size() ? uses_temp[ci] != 0 : cells[ci].usesTemperature();
    return uses ? x[layout.size()] : kReferenceTemp_C;
  }
  // A group of one cell (parallel = 1): the cell carries the group's current i_A, and
  // its terminal voltage is the group's (splitGroup's case, for a caller that has the
  // cell's EMF and R0 at hand).
  static double singleCellVoltage(double i_A, double emf_V, double r0_ohm) { return emf_V - i_A * r0_ohm; }
  // Thevenin equivalent of group g: EMF (V) and resistance (Ω); i_sign_A < 0 selects
  // the charge R0.
  template <typename CellStates>
  void groupThevenin(int g, CellStates x_cell, double& e_V, double& r_ohm, double i_sign_A = 0.0) const;
  // Splits group g's current from its cells' EMF behind R0 (OCV minus RC polarisation,
  // plus the instantaneous hysteresis for this current) and R0 (for this current's
  // sign), evaluated by the caller once per cell: emf_cell[i], r0_cell[i] at the cell
  // indices i = g·Mp … g·Mp+Mp-1. Writes the cells' currents into i_cell; returns V_g.
  double splitGroup(int g, double i_group_A, const double* emf_cell, const double* r0_cell, double* i_cell) const {
    const int first = g * parallel;
    if (parallel == 1) {  // the cell carries the group's current
      i_cell[first] = i_group_A;
      return singleCellVoltage(i_group_A, emf_cell[first], r0_cell[first]);
    }
    double sum_e_over_r = 0.0, sum_g = 0.0;
    for (int i = first; i < first + parallel; ++i) {
      const double gk = 1.0 / r0_cell[i];
      sum_e_over_r += emf_cell[i] * gk;
      sum_g += gk;
    }
    const double v_g = (sum_e_over_r - i_group_A) / sum_g;
    for (int i = first; i < first + parallel; ++i) i_cell[i] = (emf_cell[i] - v_g) / r0_cell[i];
    return v_g;
  }
};

template <typename CellStates>
void Pack::groupThevenin(int g, CellStates x_cell, double& e_V, double& r_ohm, double i_sign_A) const {
  const int first = g * parallel;
  double sum_e_over_r = 0.0, sum_g = 0.0;
  for (int k = 0; k < parallel; ++k) {
    const CellParams& p = cells[first + k];
    const double* x = x_cell(first + k);
    const double t_C = cellTemp_C(first + k, x);
    const double gk = 1.0 / ecm::r0(p, x[CellLayout::soc], t_C, i_sign_A);
    sum_e_over_r += (ecm::emfAt(p, x, t_C) + ecm::instantHysteresis_V(p, i_sign_A)) * gk;
    sum_g += gk;
  }
  e_V = sum_e_over_r / sum_g;
  r_ohm = 1.0 / sum_g;
}

}  // namespace packsim
