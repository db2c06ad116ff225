// Equivalent-circuit (Thevenin) cell: an OCV source, a series resistance and N RC pairs,
// each element a function of the state of charge and, optionally, the cell temperature.
//
//   states    soc            state of charge, 1 = full
//             v_rc[k]        voltage across RC pair k [V]
//             h              hysteresis voltage [V] (only with a hysteresis block)
//   inputs    i_A            cell current [A], positive discharges
//             T              cell temperature [°C] (a node of the thermal network)
//   equations d soc/dt    = -(eta(i)·i + i_sd + i_int) / (3600·Q)
//                           i_int: current through an internal short (not at the terminals)
//                           eta = 1 on discharge, coulombic_efficiency on charge
//             d v_rc[k]/dt = i / C_k(soc,T) - v_rc[k] / (R_k(soc,T)·C_k(soc,T))
//             d h/dt      = γ·|i|/3600 · (-M(soc,T)·sgn(i) - h)    one-state hysteresis:
//                           h tends to -M while discharging, +M while charging
//   output    v_term = OCV(soc,T) + h - M0·sgn(i) - i·R0(soc,T,sign i) - Σ v_rc[k]
//             R0 on charge (i < 0) is r0_charge_ohm when given, else r0_ohm;
//             M0 the instantaneous hysteresis (0 by default)
//   heat      q_W = i²·R0 + Σ v_rc[k]² / R_k       Joule heat in R0 and the RC resistors
//                 - i·T_K·dOCV/dT(soc)              reversible (entropic) heat, when given:
//                                                   absorbed on discharge where dOCV/dT > 0
//                 - i·(h - M0·sgn(i))               hysteresis loss, when given
//
// Curves over discharged Ah use the nominal capacity axis_capacity_Ah (the preset's),
// not the cell's own: see models/cell/curve.hpp. The struct is a constant description:
// no state; the cell's temperature lives in the thermal network.
#pragma once
#include <vector>

#include "models/cell/curve.hpp"

namespace packsim {

struct RcPair {
  // A pair with constant elements: r_ohm and c_F. A pair whose R or τ (or C) varies
  // with SOC or temperature carries its curves and variable = true.
  double r_ohm = 0.0;
  double c_F = 0.0;
  bool variable = false;
  bool by_tau = false;  // variable: C = τ(soc,T)/R(soc,T); else C = c_curve(soc,T)
  Curve r_curve, c_curve, tau_curve;
  double tau_s() const { return r_ohm * c_F; }  // constant pair
};

struct CellParams {
  double capacity_Ah = 1.0;
  double axis_capacity_Ah = 0.0;      // Q of the curves' discharged_Ah axis; 0: capacity_Ah
  Curve ocv_V = Curve::constant(3.7);
  Curve r0_ohm = Curve::constant(0.01);
  bool has_r0_charge = false;         // R0 when charging differs from r0_ohm
  Curve r0_charge_ohm = Curve::constant(0.01);
  bool has_entropic = false;          // reversible heat from dOCV/dT
  Curve docv_dT_V_per_K = Curve::constant(0.0);
  bool has_hysteresis = false;        // one more state per cell: h
  Curve hysteresis_max_V = Curve::constant(0.0);  // M(soc,T)
  double hysteresis_rate_per_Ah = 0.0;            // γ
  double hysteresis_instant_V = 0.0;              // M0
  double r0_scale = 1.0;              // per-cell spread of R0 around the curve
  std::vector<RcPair> rc;
  double coulombic_efficiency = 1.0;  // applied to charging current
  double self_discharge_A = 0.0;      // constant leakage, drains SOC at rest
  double heat_capacity_J_per_K = 50.0;
  double g_ambient_W_per_K = 0.05;    // cell surface to ambient
  double v_min_V = 2.5;               // chemistry limits (for reports, not enforced)
  double v_max_V = 4.2;
  // Datasheet ratings (0: not stated). Not used by the model: the loader derives the
  // over-current limits of a pack that states none from them (docs/scenario.md).
  double max_charge_C = 0.0;
  double max_discharge_C = 0.0;

  double axisCapacity_Ah() const { return axis_capacity_Ah > 0.0 ? axis_capacity_Ah : capacity_Ah; }
  // Whether any element reads the cell temperature (else it is never looked up).
  bool usesTemperature() const;
};

// Index map of one cell's electrical states; the thermal state lives in the network.
struct CellLayout {
  int n_rc = 0;
  bool hysteresis = false;
  int size() const { return 1 + n_rc + (hysteresis ? 1 : 0); }
  static constexpr int soc = 0;
  int rc(int k) const { return 1 + k; }
  int hyst() const { return 1 + n_rc; }  // valid when hysteresis
};

namespace ecm {

double ocv(const CellParams& p, double soc, double temp_C = kReferenceTemp_C);
// R0 for a current i_A (positive discharges; i_A < 0 selects the charge R0).
double r0(const CellParams& p, double soc, double temp_C = kReferenceTemp_C, double i_A = 0.0);
inline double rcR_ohm(const RcPair& rc, const CellParams& p, double soc, double temp_C) {
  return rc.variable ? rc.r_curve.eval(soc, p.axisCapacity_Ah(), temp_C) : rc.r_ohm;
}
double rcC_F(const RcPair& rc, const CellParams& p, double soc, double temp_C);
// OCV minus RC polarisation: the voltage behind R0.
double emfAt(const CellParams& p, const double* x, double temp_C);
double emf(const CellParams& p, const double* x);  // at kReferenceTemp_C
// The same with the OCV already evaluated at the cell's SOC (ocv_V = ocv(p, soc, T)).
// Inline: the plant reads it per cell and evaluation.
inline double emf(const CellParams& p, const double* x, double ocv_V) {
  double v = ocv_V;
  for (size_t k = 0; k < p.rc.size(); ++k) v -= x[1 + k];
  if (p.has_hysteresis) v += x[1 + p.rc.size()];
  return v;
}
double terminalVoltage(const CellParams& p, const double* x, double i_A, double temp_C = kReferenceTemp_C);
double heat_W(const CellParams& p, const double* x, double i_A);  // at kReferenceTemp_C
// Heat with R0 already evaluated at the cell's SOC (r0_ohm = r0(p, soc, T, i)).
double heatWithR0_W(const CellParams& p, const double* x, double i_A, double r0_ohm, double temp_C);
// The instantaneous hysteresis term -M0·sgn(i) (0 without hysteresis or current).
inline double instantHysteresis_V(const CellParams& p, double i_A) {
  if (!p.has_hysteresis) return 0.0;
  return i_A > 0.0 ? -p.hysteresis_instant_V : i_A < 0.0 ? p.hysteresis_instant_V : 0.0;
}
// Heat with R0 and the reversible heat evaluated too (reversible_W = reversibleHeat_W(p,
// soc, i, T)): the plant keeps the latter for the chemical-energy quadrature.
inline double heatWithParts_W(const CellParams& p, const double* x, double i_A, double r0_ohm, double reversible_W,
                              double temp_C) {
  double q = i_A * i_A * r0_ohm;
  for (size_t k = 0; k < p.rc.size(); ++k) q += x[1 + k] * x[1 + k] / rcR_ohm(p.rc[k], p, x[CellLayout::soc], temp_C);
  if (p.has_entropic) q += reversible_W;
  if (p.has_hysteresis) q -= i_A * (x[1 + p.rc.size()] + instantHysteresis_V(p, i_A));
  return q;
}
// Reversible heat alone: -i·T_K·dOCV/dT (0 without a dOCV/dT curve).
double reversibleHeat_W(const CellParams& p, double soc, double i_A, double temp_C);
// The SOC's rate: charge into the cell (eta on charging), its leakage and any internal
// draw, over its charge_As = 3600·capacity_Ah.
inline double socRate(double eta, double i_A, double self_discharge_A, double internal_A, double charge_As) {
  return -(eta * i_A + self_discharge_A + internal_A) / charge_As;
}
// An RC pair's voltage rate: i/C - v/(R·C), with tau_s = R·C.
inline double rcRate(double i_A, double c_F, double tau_s, double v) { return i_A / c_F - v / tau_s; }
// Writes d/dt of the electrical states into dx (same layout as x).
void derivatives(const CellParams& p, const double* x, double i_A, double* dx, double internal_A = 0.0,
                 double temp_C = kReferenceTemp_C);

}  // namespace ecm
}  // namespace packsim
