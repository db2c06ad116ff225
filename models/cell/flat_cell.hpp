// One cell's curves laid out for the plant's per-cell loop (FlatCurve), with the
// constants ecm:: reads from CellParams on every call, built once when the plant is.
// Each method is its ecm:: function to the bit (tests/models/ecm_test.cpp):
//
//   ocv_V              ecm::ocv (outside SOC 0…1 it is ecm::ocv itself: the rare
//                      extrapolation along the last 1 % is not worth a second copy)
//   r0_ohm             ecm::r0 (the charge R0 for i_A < 0 when the cell has one)
//   reversibleHeat_W   ecm::reversibleHeat_W
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
  FlatCurve ocv, r0, r0_charge, docv_dT;
  double axis_capacity_Ah = 1.0;
  double r0_scale = 1.0;
  bool has_r0_charge = false;
  bool has_entropic = false;

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
    return f;
  }

  // p: the cell this was built from.
  double ocv_V(const CellParams& p, double soc, double temp_C, CellHints& h) const {
    if (soc >= 0.0 && soc <= 1.0) return ocv.eval(soc, axis_capacity_Ah, temp_C, h.ocv);
    return ecm::ocv(p, soc, temp_C);
  }
  double r0_ohm(double soc, double temp_C, double i_A, CellHints& h) const {
    if (i_A < 0.0 && has_r0_charge) return r0_scale * r0_charge.eval(soc, axis_capacity_Ah, temp_C, h.r0_charge);
    return r0_scale * r0.eval(soc, axis_capacity_Ah, temp_C, h.r0);
  }
  double reversibleHeat_W(double soc, double i_A, double temp_C, CellHints& h) const {
    if (!has_entropic) return 0.0;
    return -i_A * (temp_C + kZeroCelsius_K) * docv_dT.eval(soc, axis_capacity_Ah, temp_C, h.docv_dT);
  }
};

}  // namespace packsim
