#include "models/cell/ecm.hpp"

namespace packsim::ecm {

double ocv(const CellParams& p, double soc) { return p.ocv_V.eval(soc, p.capacity_Ah); }

double r0(const CellParams& p, double soc) { return p.r0_scale * p.r0_ohm.eval(soc, p.capacity_Ah); }

double emf(const CellParams& p, const double* x) { return emf(p, x, ocv(p, x[CellLayout::soc])); }

double emf(const CellParams& p, const double* x, double ocv_V) {
  double v = ocv_V;
  for (size_t k = 0; k < p.rc.size(); ++k) v -= x[1 + k];
  return v;
}

double terminalVoltage(const CellParams& p, const double* x, double i_A) {
  return emf(p, x) - i_A * r0(p, x[CellLayout::soc]);
}

double heat_W(const CellParams& p, const double* x, double i_A) { return heat_W(p, x, i_A, r0(p, x[CellLayout::soc])); }

double heat_W(const CellParams& p, const double* x, double i_A, double r0_ohm) {
  double q = i_A * i_A * r0_ohm;
  for (size_t k = 0; k < p.rc.size(); ++k) q += x[1 + k] * x[1 + k] / p.rc[k].r_ohm;
  return q;
}

void derivatives(const CellParams& p, const double* x, double i_A, double* dx, double internal_A) {
  const double eta = i_A < 0.0 ? p.coulombic_efficiency : 1.0;
  dx[CellLayout::soc] = -(eta * i_A + p.self_discharge_A + internal_A) / (3600.0 * p.capacity_Ah);
  for (size_t k = 0; k < p.rc.size(); ++k) {
    const RcPair& rc = p.rc[k];
    dx[1 + k] = i_A / rc.c_F - x[1 + k] / (rc.r_ohm * rc.c_F);
  }
}

}  // namespace packsim::ecm
