// A cheap sine and cosine of a Box-Muller angle a in [0, 2π], with a bound on how far
// each lies from the libm's std::sin(a) / std::cos(a): what a noise draw needs to know
// which code a conversion lands on without the libm's sincos (some 130 instructions).
//
//   approxSinCos(a, s, c)   |s - std::sin(a)| <= kApproxSinCosBound, the same for c
//
// From a table of the libm's sine and cosine at 257 angles a_k ~ 2πk/256 (built once):
// with d = a - a_k for the nearest a_k (|d| <= π/256), sin(a) = S_k·cos d + C_k·sin d and
// cos(a) = C_k·cos d - S_k·sin d, sin d and cos d by their series to d^5 and d^6
// (truncation below 1e-17). Some 1e-16 from the libm's values altogether: the bound,
// 1e-12, leaves four orders of magnitude (the whole range checked against the libm in
// lazy_normal_test.cpp).
#pragma once

namespace packsim {

constexpr double kApproxSinCosBound = 1e-12;

struct SinCosTable {
  static constexpr int kSteps = 256;  // per turn
  struct Entry {
    double a, s, c;  // a_k, std::sin(a_k), std::cos(a_k)
  };
  Entry at[kSteps + 1];
};
extern const SinCosTable kSinCosTable;  // approx_sincos.cpp

inline void approxSinCos(double a, double& s, double& c) {
  constexpr double kStepsPerRadian = SinCosTable::kSteps / 6.283185307179586;
  const SinCosTable::Entry& e = kSinCosTable.at[static_cast<int>(a * kStepsPerRadian + 0.5)];  // a >= 0
  const double d = a - e.a, z = d * d;
  const double sinD = d + d * z * (-1.0 / 6.0 + z * (1.0 / 120.0));
  const double cosD = 1.0 + z * (-0.5 + z * (1.0 / 24.0 - z * (1.0 / 720.0)));
  s = e.s * cosD + e.c * sinD;
  c = e.c * cosD - e.s * sinD;
}

}  // namespace packsim
