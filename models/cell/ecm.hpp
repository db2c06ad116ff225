// Equivalent-circuit (Thevenin) cell: an OCV source, a series resistance and N RC pairs.
//
//   states    soc            state of charge, 1 = full
//             v_rc[k]        voltage across RC pair k [V]
//   input     i_A            cell current [A], positive discharges
//   equations d soc/dt    = -(eta(i)·i + i_sd + i_int) / (3600·Q)
//                           i_int: current through an internal short (not at the terminals)
//                           eta = 1 on discharge, coulombic_efficiency on charge
//             d v_rc[k]/dt = i / C_k - v_rc[k] / (R_k·C_k)
//   output    v_term = OCV(soc) - i·R0(soc) - Σ v_rc[k]
//   heat      q_W = i²·R0 + Σ v_rc[k]² / R_k    (Joule heat in R0 and the RC resistors)
//
// The cell's temperature is a node of the thermal network (models/thermal); the
// cell only reports its heat. The struct is a constant description: no state.
#pragma once
#include <vector>

#include "models/cell/curve.hpp"

namespace packsim {

struct RcPair {
  double r_ohm = 0.0;
  double c_F = 0.0;
  double tau_s() const { return r_ohm * c_F; }
};

struct CellParams {
  double capacity_Ah = 1.0;
  Curve ocv_V = Curve::constant(3.7);
  Curve r0_ohm = Curve::constant(0.01);
  double r0_scale = 1.0;              // per-cell spread of R0 around the curve
  std::vector<RcPair> rc;
  double coulombic_efficiency = 1.0;  // applied to charging current
  double self_discharge_A = 0.0;      // constant leakage, drains SOC at rest
  double heat_capacity_J_per_K = 50.0;
  double g_ambient_W_per_K = 0.05;    // cell surface to ambient
  double v_min_V = 2.5;               // chemistry limits (for reports, not enforced)
  double v_max_V = 4.2;
};

// Index map of one cell's electrical states; the thermal state lives in the network.
struct CellLayout {
  int n_rc = 0;
  int size() const { return 1 + n_rc; }
  static constexpr int soc = 0;
  int rc(int k) const { return 1 + k; }
};

namespace ecm {

double ocv(const CellParams& p, double soc);
double r0(const CellParams& p, double soc);
// OCV minus RC polarisation: the voltage behind R0.
double emf(const CellParams& p, const double* x);
// The same with the OCV already evaluated at the cell's SOC (ocv_V = ocv(p, soc)).
double emf(const CellParams& p, const double* x, double ocv_V);
double terminalVoltage(const CellParams& p, const double* x, double i_A);
double heat_W(const CellParams& p, const double* x, double i_A);
// The same with R0 already evaluated at the cell's SOC (r0_ohm = r0(p, soc)).
double heat_W(const CellParams& p, const double* x, double i_A, double r0_ohm);
// Writes d/dt of the electrical states into dx (same layout as x).
void derivatives(const CellParams& p, const double* x, double i_A, double* dx, double internal_A = 0.0);

}  // namespace ecm
}  // namespace packsim
