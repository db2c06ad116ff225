// The floor: the bare per-cell arithmetic of the plant over flat arrays -- what no
// simulator of this model can beat on this machine. No BMS, no sensors, no recording,
// no parallel current split, no quadratures, no virtual calls: one loop over cells.
//
// One step of length h for cell i at current I_i (positive discharges), the same
// update the fast integrator (core/sim/fast_integrator.hpp) makes:
//
//   OCV   = ocv(soc, T)              R0 = r0_scale_i · r0(soc, T)   (the cell's curves)
//   v     = OCV - I·R0 - Σ v_k       terminal voltage (the output)
//   q     = I²·R0 + Σ v_k² / R_k     Joule heat
//           - I·T_K·dOCV/dT(soc)     reversible heat (when the cell has an entropic curve)
//   soc  -= h·(η(I)·I + I_sd) / (3600·Q_i)                        explicit
//   v_k   = v_k·a_k + I·R_k·(1 - a_k),   a_k = e^{-h/τ_k}        exact exponential
//   T    += h/C_i · (q - G_amb,i·(T - T_amb) - G_link·(2T - T_left - T_right))
//
// The curves are the cell preset's own (table, table over temperature, or polynomial,
// on SOC or discharged-Ah axis, with their Arrhenius factor; evaluated exactly as
// models/cell/curve.cpp does) copied into fixed arrays: the temperature dependence
// belongs to the model, so the floor pays for it too.
// Parameters and states are structures of arrays; a_k are precomputed for h.
#pragma once
#include <vector>

#include "core/sim/plant.hpp"

namespace packsim::bench {

// A Curve flattened into fixed storage (tables and polynomials up to kMax points, up to
// kMaxRows temperature rows).
struct FlatCurve {
  static constexpr int kMax = 32, kMaxRows = 8;
  int kind = 0;            // 0 constant, 1 polynomial, 2 table, 3 table over temperature
  bool discharged_axis = false;
  int n = 0, rows = 0;
  double arrhenius_K = 0.0, ref_temp_C = 0.0;
  double x[kMax] = {}, t[kMaxRows] = {}, y[kMax * kMaxRows] = {};  // polynomial coefficients in y

  static FlatCurve from(const Curve& c);
  double eval(double soc, double capacity_Ah, double temp_C) const;
};

class FloorPack {
 public:
  // Cells, curves, spread and the initial state of a plant; thermal links between
  // neighbouring cells at the plant's cell-to-cell conductance (0 if none).
  FloorPack(const Plant& plant, double cell_to_cell_W_per_K, double ambient_C);

  int cells() const { return n_; }
  // Precomputes a_k = e^{-h/τ_k} and the per-cell factors for step length h.
  void prepare(double h_s);
  // One step of every cell at the same cell current i_A (a series string; the floor
  // has no parallel current split); terminal voltages into v_V. Returns Σ v (a
  // checksum that keeps the work observable).
  double step(double i_A, double* v_V);

  double soc(int c) const { return soc_[static_cast<size_t>(c)]; }
  double vrc(int c, int k) const { return vrc_[static_cast<size_t>(k * n_ + c)]; }
  double temp_C(int c) const { return temp_[static_cast<size_t>(c)]; }

 private:
  int n_ = 0, nrc_ = 0;
  FlatCurve ocv_, r0_, docvDt_;
  bool entropic_ = false;
  double ambient_C_ = 25.0, gLink_ = 0.0, h_ = 0.0;
  // parameters (per cell; RC per pair k at k·n + c)
  std::vector<double> cap_Ah_, axisCap_Ah_, r0Scale_, eff_, selfDis_A_, heatCap_, gAmb_, rcR_, rcTau_;
  // derived for h
  std::vector<double> socGain_, tempGain_, rcA_;
  // states
  std::vector<double> soc_, vrc_, temp_;
};

// Keeps a value (and the memory behind a pointer) alive for the optimiser.
template <typename T>
inline void doNotOptimize(const T& v) {
  asm volatile("" : : "r,m"(v) : "memory");
}

}  // namespace packsim::bench
