// One cell's curves laid out for the plant's per-cell loop (FlatCurve), with the
// constants ecm:: reads from CellParams on every call, built once when the plant is.
// Each method is its ecm:: function to the bit (tests/models/ecm_test.cpp):
//
//   ocv_V              ecm::ocv (outside SOC 0…1 it is ecm::ocv itself: the rare
//                      extrapolation along the last 1 % is not worth a second copy)
//   r0_ohm             ecm::r0 (the charge R0 for i_A < 0 when the cell has one)
//   reversibleHeat_W   ecm::reversibleHeat_W
//   emf_V              ecm::emf(p, x, ocv) + ecm::instantHysteresis_V(p, i_A)
//   heat_W             ecm::heatWithParts_W (the RC resistances read from here when
//                      every pair is constant and there are at most kFlatRc of them)
//   temp_C             Pack::cellTemp_C: the cell's temperature slot if a curve reads it
//   derivatives        ecm::derivatives (inline for constant pairs without hysteresis, with
//                      the products it forms per call, 3600·Q and each pair's R·C, kept)
//
// The hints (CellHints) belong to the caller: the plant keeps them per cell in its
// signals, so a const Plant evaluated from several places never shares them.
#pragma once
#include "models/cell/ecm.hpp"
#include "models/cell/flat_curve.hpp"

namespace packsim {

struct CellHints {
  CurveHint ocv, r0, r0_charge, docv_dT;
};

struct FlatCell {
  static constexpr int kFlatRc = 4;  // constant RC pairs kept here (a cell has one or two)

  FlatCurve ocv, r0, r0_charge, docv_dT;
  double axis_capacity_Ah = 1.0;
  double r0_scale = 1.0;
  bool has_r0_charge = false;
  bool has_entropic = false;
  bool has_hysteresis = false;
  bool uses_temp = false;        // CellParams::usesTemperature
  bool rc_constant = true;       // every pair constant and at most kFlatRc: rc_r_ohm holds them
  int n_rc = 0;
  double hysteresis_instant_V = 0.0;
  double rc_r_ohm[kFlatRc] = {};
  double rc_c_F[kFlatRc] = {};
  double rc_tau_s[kFlatRc] = {};  // r_ohm·c_F, as ecm::derivatives forms it
  double coulombic_efficiency = 1.0;
  double self_discharge_A = 0.0;
  double charge_As = 3600.0;      // 3600·capacity_Ah, as ecm::derivatives forms it

  static FlatCell of(const CellParams& p) {
    FlatCell f;
    f.ocv = FlatCurve::of(p.ocv_V);
    f.r0 = FlatCurve::of(p.r0_ohm);
    f.r0_charge = FlatCurve::of(p.r0_charge_ohm);
    f.docv_dT = FlatCurve::of(p.docv_dT_V_per_K);
    f.axis_capacity_Ah = p.axisCapacity_Ah();
    f.r0_scale = p.r0_scale;
    f.has_r0_charge = p.has_r0_charge;
    f.has_entropic = p.has_entropic;
    f.has_hysteresis = p.has_hysteresis;
    f.uses_temp = p.usesTemperature();
    f.n_rc = static_cast<int>(p.rc.size());
    f.hysteresis_instant_V = p.hysteresis_instant_V;
    f.rc_constant = f.n_rc <= kFlatRc;
    for (int k = 0; k < f.n_rc && f.rc_constant; ++k) {
      const RcPair& rc = p.rc[static_cast<size_t>(k)];
      f.rc_constant = !rc.variable;
      f.rc_r_ohm[k] = rc.r_ohm;
      f.rc_c_F[k] = rc.c_F;
      f.rc_tau_s[k] = rc.r_ohm * rc.c_F;
    }
    f.coulombic_efficiency = p.coulombic_efficiency;
    f.self_discharge_A = p.self_discharge_A;
    f.charge_As = 3600.0 * p.capacity_Ah;
    return f;
  }

  // x: the cell's states; temp_slot: its temperature's index there (CellLayout::size()).
  double temp_C(const double* x, int temp_slot) const { return uses_temp ? x[temp_slot] : kReferenceTemp_C; }

  // p: the cell this was built from.
  // ocv_V, r0_ohm and reversibleHeat_W always inlined, like the FlatCurve::eval they call:
  // left to -O2, ocv_V and reversibleHeat_W went out of line once eval took the polynomial
  // too (some 50 instructions a tick more on one cell).
  [[gnu::always_inline]] double ocv_V(const CellParams& p, double soc, double temp_C, CellHints& h) const {
    if (soc >= 0.0 && soc <= 1.0) return ocv.eval(soc, axis_capacity_Ah, temp_C, h.ocv);
    return ecm::ocv(p, soc, temp_C);
  }
  [[gnu::always_inline]] double r0_ohm(double soc, double temp_C, double i_A, CellHints& h) const {
    if (i_A < 0.0 && has_r0_charge) return r0_scale * r0_charge.eval(soc, axis_capacity_Ah, temp_C, h.r0_charge);
    return r0_scale * r0.eval(soc, axis_capacity_Ah, temp_C, h.r0);
  }
  [[gnu::always_inline]] double reversibleHeat_W(double soc, double i_A, double temp_C, CellHints& h) const {
    if (!has_entropic) return 0.0;
    return -i_A * (temp_C + kZeroCelsius_K) * docv_dT.eval(soc, axis_capacity_Ah, temp_C, h.docv_dT);
  }
  double instantHysteresis_V(double i_A) const {
    if (!has_hysteresis) return 0.0;
    return i_A > 0.0 ? -hysteresis_instant_V : i_A < 0.0 ? hysteresis_instant_V : 0.0;
  }
  // x: the cell's states (layout: soc, v_rc…, h).
  double emf_V(const double* x, double ocv_V, double i_A) const {
    double v = ocv_V;
    switch (n_rc) {  // the usual cell's one or two pairs without the loop's count and branches
      case 1: v -= x[1]; break;
      case 2: v -= x[1]; v -= x[2]; break;
      default: for (int k = 0; k < n_rc; ++k) v -= x[1 + k];
    }
    if (has_hysteresis) v += x[1 + n_rc];
    return v + instantHysteresis_V(i_A);
  }
  // p: the cell this was built from (its RC curves when rc_constant is false).
  double heat_W(const CellParams& p, const double* x, double i_A, double r0_ohm, double reversible_W,
                double temp_C) const {
    double q = i_A * i_A * r0_ohm;
    if (rc_constant) {
      for (int k = 0; k < n_rc; ++k) q += x[1 + k] * x[1 + k] / rc_r_ohm[k];
    } else {
      for (int k = 0; k < n_rc; ++k)
        q += x[1 + k] * x[1 + k] / ecm::rcR_ohm(p.rc[static_cast<size_t>(k)], p, x[CellLayout::soc], temp_C);
    }
    if (has_entropic) q += reversible_W;
    if (has_hysteresis) q -= i_A * (x[1 + n_rc] + instantHysteresis_V(i_A));
    return q;
  }
  // ecm::derivatives(p, x, i_A, dx, internal_A, temp_C): the same operations in the same
  // order. Inline for the usual cell (constant pairs, no hysteresis), which saves the call
  // and its walk over p.rc (some 30 instructions per cell and plant evaluation); any other
  // cell calls it.
  [[gnu::always_inline]] void derivatives(const CellParams& p, const double* x, double i_A, double* dx,
                                          double internal_A, double temp_C) const {
    if (!rc_constant || has_hysteresis) {
      ecm::derivatives(p, x, i_A, dx, internal_A, temp_C);
      return;
    }
    const double eta = i_A < 0.0 ? coulombic_efficiency : 1.0;
    dx[CellLayout::soc] = ecm::socRate(eta, i_A, self_discharge_A, internal_A, charge_As);
    for (int k = 0; k < n_rc; ++k) dx[1 + k] = ecm::rcRate(i_A, rc_c_F[k], rc_tau_s[k], x[1 + k]);
  }
};

}  // namespace packsim
