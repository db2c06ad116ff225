#include "bench/floor_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace packsim::bench {

FlatCurve FlatCurve::from(const Curve& c) {
  FlatCurve f;
  f.discharged_axis = c.axis == CurveAxis::Discharged_Ah;
  f.arrhenius_K = c.arrhenius_K;
  f.ref_temp_C = c.ref_temp_C;
  const bool table = c.kind == Curve::Kind::Table || c.kind == Curve::Kind::Table2D;
  const std::vector<double>& ys = table ? c.ys() : c.coeffs();
  f.kind = c.kind == Curve::Kind::Constant ? 0 : c.kind == Curve::Kind::Polynomial ? 1 : table && c.kind == Curve::Kind::Table ? 2 : 3;
  f.n = table ? static_cast<int>(c.xs().size()) : static_cast<int>(ys.size());
  f.rows = f.kind == 3 ? static_cast<int>(c.temps_C().size()) : 1;
  if (f.n > kMax || f.rows > kMaxRows) throw std::invalid_argument("floor kernel: curve larger than 32 points x 8 rows");
  for (size_t i = 0; i < ys.size(); ++i) f.y[i] = ys[i];
  for (int i = 0; table && i < f.n; ++i) f.x[i] = c.xs()[static_cast<size_t>(i)];
  for (int j = 0; f.kind == 3 && j < f.rows; ++j) f.t[j] = c.temps_C()[static_cast<size_t>(j)];
  return f;
}

// Same arithmetic as Curve::eval / Curve::at (models/cell/curve.cpp).
double FlatCurve::eval(double soc, double capacity_Ah, double temp_C) const {
  if (kind == 0 && arrhenius_K == 0.0) return y[0];
  const double xv = discharged_axis ? (1.0 - soc) * capacity_Ah : soc;
  double r = y[0];
  if (kind == 1) {
    r = 0.0;
    for (int i = 0; i < n; ++i) r = r * xv + y[i];
  } else if (kind == 2) {
    r = interpolateN(x, y, static_cast<size_t>(n), xv);
  } else if (kind == 3) {
    return interpolateGrid(x, y, static_cast<size_t>(n), t, static_cast<size_t>(rows), xv, temp_C);
  }
  if (arrhenius_K == 0.0) return r;
  return r * arrheniusFactor(arrhenius_K, temp_C, ref_temp_C);
}

FloorPack::FloorPack(const Plant& plant, double cell_to_cell_W_per_K, double ambient_C)
    : n_(plant.pack().cellCount()), nrc_(plant.pack().layout.n_rc), ambient_C_(ambient_C),
      gLink_(cell_to_cell_W_per_K) {
  const Pack& pk = plant.pack();
  const CellParams& cell = pk.cells.front();
  for (const RcPair& k : cell.rc)
    if (k.variable) throw std::invalid_argument("floor kernel: RC pairs over SOC or temperature are not flattened");
  if (cell.has_hysteresis || cell.has_r0_charge)
    throw std::invalid_argument("floor kernel: hysteresis and a charge R0 are not flattened");
  ocv_ = FlatCurve::from(cell.ocv_V);
  r0_ = FlatCurve::from(cell.r0_ohm);
  entropic_ = cell.has_entropic;
  if (entropic_) docvDt_ = FlatCurve::from(cell.docv_dT_V_per_K);
  const size_t n = static_cast<size_t>(n_), nr = static_cast<size_t>(nrc_);
  std::vector<double> x(static_cast<size_t>(plant.stateSize()));
  plant.initialState(x.data());
  rcR_.resize(n * nr);
  rcTau_.resize(n * nr);
  vrc_.resize(n * nr);
  for (size_t c = 0; c < n; ++c) {
    const CellParams& p = pk.cells[c];
    cap_Ah_.push_back(p.capacity_Ah);
    axisCap_Ah_.push_back(p.axisCapacity_Ah());  // curves over discharged Ah: the nominal Q
    r0Scale_.push_back(p.r0_scale);
    eff_.push_back(p.coulombic_efficiency);
    selfDis_A_.push_back(p.self_discharge_A);
    heatCap_.push_back(p.heat_capacity_J_per_K);
    gAmb_.push_back(p.g_ambient_W_per_K);
    const double* xc = plant.cellStates(x.data(), static_cast<int>(c));
    soc_.push_back(xc[CellLayout::soc]);
    temp_.push_back(x[static_cast<size_t>(plant.tempIndex(static_cast<int>(c)))]);
    for (size_t k = 0; k < nr; ++k) {
      rcR_[k * n + c] = p.rc[k].r_ohm;
      rcTau_[k * n + c] = p.rc[k].tau_s();
      vrc_[k * n + c] = xc[1 + k];
    }
  }
  socGain_.resize(n);
  tempGain_.resize(n);
  rcA_.resize(n * nr);
}

void FloorPack::prepare(double h_s) {
  h_ = h_s;
  for (size_t c = 0; c < static_cast<size_t>(n_); ++c) {
    socGain_[c] = h_s / (3600.0 * cap_Ah_[c]);
    tempGain_[c] = h_s / heatCap_[c];
  }
  for (size_t j = 0; j < rcA_.size(); ++j) rcA_[j] = std::exp(-h_s / rcTau_[j]);
}

double FloorPack::step(double i, double* v_V) {
  const int n = n_;
  double sum = 0.0;
  double tLeftOld = 0.0;  // old temperature of cell c-1 (already overwritten in temp_)
  for (int c = 0; c < n; ++c) {
    const double soc = soc_[c], T = temp_[c];
    const double ocv = ocv_.eval(soc, axisCap_Ah_[c], T);
    const double r0 = r0Scale_[c] * r0_.eval(soc, axisCap_Ah_[c], T);
    double v = ocv - i * r0;
    double q = i * i * r0;
    if (entropic_) q -= i * (T + kZeroCelsius_K) * docvDt_.eval(soc, axisCap_Ah_[c], T);
    for (int k = 0; k < nrc_; ++k) {
      const size_t j = static_cast<size_t>(k * n + c);
      const double vk = vrc_[j];
      v -= vk;
      q += vk * vk / rcR_[j];
      vrc_[j] = vk * rcA_[j] + i * rcR_[j] * (1.0 - rcA_[j]);
    }
    v_V[c] = v;
    sum += v;
    const double eta = i < 0.0 ? eff_[c] : 1.0;
    soc_[c] = soc - socGain_[c] * (eta * i + selfDis_A_[c]);
    double flow = gAmb_[c] * (T - ambient_C_);
    if (c > 0) flow += gLink_ * (T - tLeftOld);
    if (c + 1 < n) flow += gLink_ * (T - temp_[c + 1]);
    tLeftOld = T;
    temp_[c] = T + tempGain_[c] * (q - flow);
  }
  return sum;
}

}  // namespace packsim::bench
