#include "models/cell/ecm.hpp"

#include <cmath>

namespace packsim {

bool CellParams::usesTemperature() const {
  if (ocv_V.dependsOnTemperature() || r0_ohm.dependsOnTemperature() || has_entropic) return true;
  if (has_hysteresis && hysteresis_max_V.dependsOnTemperature()) return true;
  if (has_r0_charge && r0_charge_ohm.dependsOnTemperature()) return true;
  for (const RcPair& k : rc)
    if (k.variable && (k.r_curve.dependsOnTemperature() || k.c_curve.dependsOnTemperature() ||
                       k.tau_curve.dependsOnTemperature()))
      return true;
  return false;
}

namespace ecm {

// Beyond empty and full the OCV continues along the slope of its last 1 % of SOC, so an
// overcharged cell's voltage keeps rising and an over-discharged one's keeps falling (a
// table held flat there would hide an overcharge from every over-voltage check).
double ocv(const CellParams& p, double soc, double temp_C) {
  const double q = p.axisCapacity_Ah();
  if (soc >= 0.0 && soc <= 1.0) return p.ocv_V.eval(soc, q, temp_C);
  constexpr double h = 0.01;
  const double end = soc > 1.0 ? 1.0 : 0.0, inside = soc > 1.0 ? 1.0 - h : h;
  const double atEnd = p.ocv_V.eval(end, q, temp_C);
  return atEnd + (soc - end) * (atEnd - p.ocv_V.eval(inside, q, temp_C)) / (end - inside);
}

double r0(const CellParams& p, double soc, double temp_C, double i_A) {
  const Curve& c = (i_A < 0.0 && p.has_r0_charge) ? p.r0_charge_ohm : p.r0_ohm;
  return p.r0_scale * c.eval(soc, p.axisCapacity_Ah(), temp_C);
}

double rcC_F(const RcPair& rc, const CellParams& p, double soc, double temp_C) {
  if (!rc.variable) return rc.c_F;
  const double q = p.axisCapacity_Ah();
  return rc.by_tau ? rc.tau_curve.eval(soc, q, temp_C) / rc.r_curve.eval(soc, q, temp_C) : rc.c_curve.eval(soc, q, temp_C);
}

double emfAt(const CellParams& p, const double* x, double temp_C) {
  return emf(p, x, ocv(p, x[CellLayout::soc], temp_C));
}

double emf(const CellParams& p, const double* x) { return emfAt(p, x, kReferenceTemp_C); }

namespace {

double sign(double i_A) { return i_A > 0.0 ? 1.0 : i_A < 0.0 ? -1.0 : 0.0; }

}  // namespace



double terminalVoltage(const CellParams& p, const double* x, double i_A, double temp_C) {
  return emfAt(p, x, temp_C) + instantHysteresis_V(p, i_A) - i_A * r0(p, x[CellLayout::soc], temp_C, i_A);
}

double heat_W(const CellParams& p, const double* x, double i_A) {
  return heatWithR0_W(p, x, i_A, r0(p, x[CellLayout::soc], kReferenceTemp_C, i_A), kReferenceTemp_C);
}

double heatWithR0_W(const CellParams& p, const double* x, double i_A, double r0_ohm, double temp_C) {
  return heatWithParts_W(p, x, i_A, r0_ohm, reversibleHeat_W(p, x[CellLayout::soc], i_A, temp_C), temp_C);
}

double reversibleHeat_W(const CellParams& p, double soc, double i_A, double temp_C) {
  if (!p.has_entropic) return 0.0;
  return -i_A * (temp_C + kZeroCelsius_K) * p.docv_dT_V_per_K.eval(soc, p.axisCapacity_Ah(), temp_C);
}

void derivatives(const CellParams& p, const double* x, double i_A, double* dx, double internal_A, double temp_C) {
  const double eta = i_A < 0.0 ? p.coulombic_efficiency : 1.0;
  dx[CellLayout::soc] = socRate(eta, i_A, p.self_discharge_A, internal_A, 3600.0 * p.capacity_Ah);
  for (size_t k = 0; k < p.rc.size(); ++k) {
    const RcPair& rc = p.rc[k];
    if (!rc.variable) {
      dx[1 + k] = rcRate(i_A, rc.c_F, rc.r_ohm * rc.c_F, x[1 + k]);
    } else {
      const double r = rcR_ohm(rc, p, x[CellLayout::soc], temp_C), c = rcC_F(rc, p, x[CellLayout::soc], temp_C);
      dx[1 + k] = rcRate(i_A, c, r * c, x[1 + k]);
    }
  }
  if (p.has_hysteresis) {
    const size_t h = 1 + p.rc.size();
    const double m = p.hysteresis_max_V.eval(x[CellLayout::soc], p.axisCapacity_Ah(), temp_C);
    dx[h] = p.hysteresis_rate_per_Ah * std::fabs(i_A) / 3600.0 * (-m * sign(i_A) - x[h]);
  }
}

}  // namespace ecm
}  // namespace packsim
