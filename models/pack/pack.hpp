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
  // Thevenin equivalent of group g: EMF (V) and resistance (Ω); i_sign_A < 0 selects
  // the charge R0.
  template <typename CellStates>
  void groupThevenin(int g, CellStates x_cell, double& e_V, double& r_ohm, double i_sign_A = 0.0) const;
  // Splits group g's current. x_cell(i) points at cell i's electrical states.
  // Writes per-cell currents into i_cell[g·Mp … g·Mp+Mp-1]; returns V_g. When given,
  // ocv_cell and r0_cell receive each cell's OCV and R0 at the same indices (the
  // curves are evaluated once per cell; callers reuse them for heat and energy).
  template <typename CellStates>
  double splitGroup(int g, double i_group_A, CellStates x_cell, double* i_cell, double* ocv_cell = nullptr,
                    double* r0_cell = nullptr) const;
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

template <typename CellStates>
double Pack::splitGroup(int g, double i_group_A, CellStates x_cell, double* i_cell, double* ocv_cell,
                        double* r0_cell) const {
  const int first = g * parallel;
  // EMF and R0 of cell i, its OCV and R0 kept if asked.
  auto cellEmf = [&](int i, double& r0) {
    const CellParams& p = cells[i];
    const double* x = x_cell(i);
    const double t_C = cellTemp_C(i, x);
    const double ocv = ecm::ocv(p, x[CellLayout::soc], t_C);
    r0 = ecm::r0(p, x[CellLayout::soc], t_C, i_group_A);
    if (ocv_cell) ocv_cell[i] = ocv;
    if (r0_cell) r0_cell[i] = r0;
    return ecm::emf(p, x, ocv) + ecm::instantHysteresis_V(p, i_group_A);
  };
  if (parallel == 1) {
    double r0 = 0.0;
    const double e = cellEmf(first, r0);
    i_cell[first] = i_group_A;
    return e - i_group_A * r0;
  }
  double sum_e_over_r = 0.0, sum_g = 0.0;
  for (int k = 0; k < parallel; ++k) {
    double r0 = 0.0;
    const double e = cellEmf(first + k, r0);
    const double gk = 1.0 / r0;
    sum_e_over_r += e * gk;
    sum_g += gk;
    i_cell[first + k] = e;  // EMF for now; the current once V_g is known
  }
  const double v_g = (sum_e_over_r - i_group_A) / sum_g;
  for (int k = 0; k < parallel; ++k) {
    const int i = first + k;
    const double r0 = r0_cell ? r0_cell[i] : ecm::r0(cells[i], x_cell(i)[CellLayout::soc], cellTemp_C(i, x_cell(i)), i_group_A);
    i_cell[i] = (i_cell[i] - v_g) / r0;
  }
  return v_g;
}

}  // namespace packsim
