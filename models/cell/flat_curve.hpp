// A Curve laid out for the plant's per-cell loop (core/sim/plant.cpp): its kind, axis and
// Arrhenius constants as plain members, its points as raw pointers into the Curve's
// shared arrays, evaluated inline with the caller's remembered table segment.
//
// FlatCurve::eval is Curve::eval to the bit: the same branches and the same operations in
// the same order (tests/models/curve_test.cpp compares them with == over random
// points of every kind). What it leaves out is only the way there: Curve::eval's three
// out-of-line calls (eval -> at -> interpolate) through the shared pointer and the
// vectors, and the table search when x is still in the segment it was in last time.
//
// The pointers are the Curve's own arrays, which every copy of the Curve shares: a
// FlatCurve stays valid while the Curve or any copy of it lives.
#pragma once
#include <cstddef>

#include "models/cell/curve.hpp"

namespace packsim {

// One caller's remembered segments of one curve: x in the table, and the 2-D grid's
// temperature.
struct CurveHint {
  SegmentHint x, temp;
};

struct FlatCurve {
  Curve::Kind kind = Curve::Kind::Constant;
  bool discharged_axis = false;  // x = (1 - SOC)·Q_axis, else x = SOC
  double arrhenius_K = 0.0;
  double ref_temp_C = kReferenceTemp_C;
  const double* coeffs = nullptr;   // polynomial (highest power first); constant: one value
  const double* xs = nullptr;       // table
  const double* ys = nullptr;       // table; 2-D: row-major [temp][x]
  const double* temps_C = nullptr;  // 2-D table
  size_t n = 0;                     // coefficients, or table points per row
  size_t rows = 0;                  // 2-D table: grid temperatures

  static FlatCurve of(const Curve& c) {
    FlatCurve f;
    f.kind = c.kind;
    f.discharged_axis = c.axis == CurveAxis::Discharged_Ah;
    f.arrhenius_K = c.arrhenius_K;
    f.ref_temp_C = c.ref_temp_C;
    f.coeffs = c.coeffs().data();
    f.xs = c.xs().data();
    f.ys = c.ys().data();
    f.temps_C = c.temps_C().data();
    const bool table = c.kind == Curve::Kind::Table || c.kind == Curve::Kind::Table2D;
    f.n = table ? c.xs().size() : c.coeffs().size();
    f.rows = c.temps_C().size();
    return f;
  }

  // == Curve::eval(soc, axis_capacity_Ah, temp_C); `hint` keeps the segments found for
  // the next call (the same caller and curve).
  // Always inlined (GCC and Clang; others ignore it): the call, not the arithmetic, was
  // most of a hinted table read, and -O2 would not inline it into the per-cell loop.
  [[gnu::always_inline]] double eval(double soc, double axis_capacity_Ah, double temp_C, CurveHint& hint) const {
    if (kind == Curve::Kind::Constant && arrhenius_K == 0.0) return coeffs[0];
    const double x = discharged_axis ? (1.0 - soc) * axis_capacity_Ah : soc;
    if (kind == Curve::Kind::Table2D) return grid(x, temp_C, hint);
    const double y = at(x, hint.x);
    if (arrhenius_K == 0.0) return y;
    return y * arrheniusFactor(arrhenius_K, temp_C, ref_temp_C);
  }

 private:
  // The 2-D table (interpolateGrid), out of line (models/cell/curve.cpp): inlined twice
  // over it would make eval too large to inline into the per-cell loop.
  double grid(double x, double temp_C, CurveHint& hint) const;
  // Curve::at(x) for a 1-D kind.
  double at(double x, SegmentHint& hint) const {
    switch (kind) {
      case Curve::Kind::Polynomial: {
        double y = 0.0;  // Horner
        for (size_t k = 0; k < n; ++k) y = y * x + coeffs[k];
        return y;
      }
      case Curve::Kind::Table:
        return interpolateN(xs, ys, n, x, &hint);
      default:  // Constant (with an Arrhenius factor)
        return coeffs[0];
    }
  }
};

}  // namespace packsim
