// A Curve laid out for the plant's per-cell loop (core/sim/plant.cpp): its kind, axis and
// Arrhenius constants as plain members, its points as raw pointers into the Curve's
// shared arrays, evaluated inline with the caller's remembered table segment.
//
// FlatCurve::eval is Curve::eval to the bit: the same branches and the same operations in
// the same order (tests/models/curve_test.cpp compares them with == over random
// points of every kind). What it leaves out is only the way there: Curve::eval's three
// out-of-line calls (eval -> at -> interpolate) through the shared pointer and the
// vectors, the table search when x is still in the segment it was in last time, and the
// reference temperature's 1/T_ref,K (a constant, worked out once).
//
// The pointers are the Curve's own arrays, which every copy of the Curve shares: a
// FlatCurve stays valid while the Curve or any copy of it lives.
#pragma once
#include <cmath>
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
  double inv_ref_K = 1.0 / (kReferenceTemp_C + kZeroCelsius_K);  // 1/T_ref,K, as arrheniusFactor forms it
  bool has_arrhenius = false;  // !(arrhenius_K == 0.0): one flag test instead of a double compare
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
    f.inv_ref_K = 1.0 / (c.ref_temp_C + kZeroCelsius_K);
    f.has_arrhenius = !(c.arrhenius_K == 0.0);
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
  // Inline: a 1-D table (a cell's usual curve), a polynomial (e.g. an R0 fit) and a plain
  // constant; the other kinds out of line (evalOther), which keeps eval small enough to
  // inline into the per-cell loop.
  [[gnu::always_inline]] double eval(double soc, double axis_capacity_Ah, double temp_C, CurveHint& hint) const {
    // evalOther's branches, taken for a table and a polynomial
    if (kind == Curve::Kind::Table) return timesArrhenius(tableAt(axisX(soc, axis_capacity_Ah), hint.x), temp_C);
    if (kind == Curve::Kind::Polynomial) return timesArrhenius(polynomialAt(axisX(soc, axis_capacity_Ah)), temp_C);
    if (kind == Curve::Kind::Constant && !has_arrhenius) return coeffs[0];
    return evalOther(soc, axis_capacity_Ah, temp_C, hint);
  }

  // == Curve::eval for every kind (models/cell/curve.cpp).
  double evalOther(double soc, double axis_capacity_Ah, double temp_C, CurveHint& hint) const;

 private:
  // Curve::axisValue.
  double axisX(double soc, double axis_capacity_Ah) const {
    return discharged_axis ? (1.0 - soc) * axis_capacity_Ah : soc;
  }
  // arrheniusFactor(arrhenius_K, temp_C, ref_temp_C): the same operations, 1/T_ref,K kept.
  double arrhenius(double temp_C) const {
    return std::exp(arrhenius_K * (1.0 / (temp_C + kZeroCelsius_K) - inv_ref_K));
  }
  // The 1-D value y with the curve's temperature factor, if it has one (Curve::at(x, T)).
  double timesArrhenius(double y, double temp_C) const { return has_arrhenius ? y * arrhenius(temp_C) : y; }
  // Curve::at's Horner loop over the coefficients (highest power first): the same
  // multiply and add per coefficient in the same order, up to eight of them unrolled (a
  // switch into a run of steps, each from the end: c[-k] is the k-th coefficient from
  // the end): a cell's R0 fit of six coefficients, evaluated per cell at every plant
  // evaluation, without the loop's count and branches (some 17 instructions an
  // evaluation; two steps a round saved half of them before).
  double polynomialAt(double x) const {
    double y = 0.0;
    const double* c = coeffs + n;
    switch (n) {
      case 8: y = y * x + c[-8]; [[fallthrough]];
      case 7: y = y * x + c[-7]; [[fallthrough]];
      case 6: y = y * x + c[-6]; [[fallthrough]];
      case 5: y = y * x + c[-5]; [[fallthrough]];
      case 4: y = y * x + c[-4]; [[fallthrough]];
      case 3: y = y * x + c[-3]; [[fallthrough]];
      case 2: y = y * x + c[-2]; [[fallthrough]];
      case 1: y = y * x + c[-1]; [[fallthrough]];
      case 0: return y;
      default: break;
    }
    for (size_t k = 0; k < n; ++k) y = y * x + coeffs[k];
    return y;
  }
  // interpolateN(xs, ys, n, x, &hint). When x lies strictly inside the remembered segment
  // (xs[h-1] < x < xs[h]), interpolateN passes its end checks (xs[0] <= xs[h-1] < x <
  // xs[h] <= xs[n-1]), its search returns that same h, and it interpolates there with
  // segmentAt: called inline here. Anything else (a miss, x on a point, NaN) goes to
  // interpolateN itself. Always inlined like eval (once eval took the polynomial too, -O2
  // left it out of line: some 600 instructions a tick more on A).
  [[gnu::always_inline]] double tableAt(double x, SegmentHint& hint) const {
    const size_t h = hint.i;
    if (h - 1 < n - 1 && xs[h - 1] < x && x < xs[h]) return segmentAt(xs, ys, h, x);  // h = 0 wraps: no hint
    return interpolateN(xs, ys, n, x, &hint);
  }
  // Curve::at(x) for a 1-D kind.
  double at(double x, SegmentHint& hint) const {
    switch (kind) {
      case Curve::Kind::Polynomial:
        return polynomialAt(x);
      case Curve::Kind::Table:
        return interpolateN(xs, ys, n, x, &hint);
      default:  // Constant (with an Arrhenius factor)
        return coeffs[0];
    }
  }
};

}  // namespace packsim
