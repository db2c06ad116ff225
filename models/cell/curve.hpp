// A scalar function of one cell variable and, optionally, the cell's temperature,
// given as a polynomial or a table.
//
//   polynomial: y = c[0]·x^n + c[1]·x^(n-1) + … + c[n]   (highest power first, as
//               numpy.polyval and spreadsheet trendlines write it)
//   table:      linear interpolation between (x[i], y[i]); held flat beyond the ends
//   table 2-D:  one row of y over x per grid temperature temps_C[j]; bilinear in
//               (x, T), held flat beyond the grid in both directions
//   Arrhenius:  any 1-D form times exp(arrhenius_K · (1/T_K - 1/T_ref_K)),
//               T_K = temp_C + 273.15 (arrhenius_K = 0: no temperature factor)
//
// The axis says what x is: state of charge (0…1) or capacity discharged in Ah,
// x = (1 - SOC)·Q_axis, where Q_axis is the *nominal* capacity of the cell the curve
// was measured on (the preset's capacity_Ah), not a weaker cell's own: every cell
// then reaches the curve's knee at its own SOC 0.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace packsim {

enum class CurveAxis { Soc, Discharged_Ah };

constexpr double kZeroCelsius_K = 273.15;
constexpr double kReferenceTemp_C = 25.0;  // where a temperature-free caller evaluates

// The points are immutable and shared: every cell of a pack built from one preset reads
// the same arrays (a copy of a Curve shares them), so a pack of thousands of cells holds
// its curves once, not once per cell.
struct Curve {
  enum class Kind { Constant, Polynomial, Table, Table2D };
  Kind kind = Kind::Constant;
  CurveAxis axis = CurveAxis::Soc;
  double arrhenius_K = 0.0;    // 0: no Arrhenius factor
  double ref_temp_C = kReferenceTemp_C;

  const std::vector<double>& coeffs() const { return pts_->coeffs; }  // polynomial, highest power first; constant: one value
  const std::vector<double>& xs() const { return pts_->xs; }          // table, strictly increasing
  const std::vector<double>& ys() const { return pts_->ys; }          // table; 2-D: row-major [temp][x]
  const std::vector<double>& temps_C() const { return pts_->temps_C; }  // 2-D table: grid temperatures, increasing

  static Curve constant(double value);
  static Curve polynomial(std::vector<double> coeffs_high_first, CurveAxis axis = CurveAxis::Soc);
  static Curve table(std::vector<double> xs, std::vector<double> ys, CurveAxis axis = CurveAxis::Soc);
  // rows[j] is y over xs at temps_C[j].
  static Curve table2d(std::vector<double> xs, std::vector<double> temps_C, const std::vector<std::vector<double>>& rows,
                       CurveAxis axis = CurveAxis::Soc);
  Curve withArrhenius(double arrhenius_K, double ref_temp_C) const;

  // Without temperature (a curve that depends on it is read at kReferenceTemp_C).
  double eval(double soc, double axis_capacity_Ah) const;
  double eval(double soc, double axis_capacity_Ah, double temp_C) const;
  double at(double x) const;                 // 1-D part on the curve's own axis
  double at(double x, double temp_C) const;  // with the temperature dependence
  // x on the curve's own axis for a state of charge.
  double axisValue(double soc, double axis_capacity_Ah) const {
    return axis == CurveAxis::Soc ? soc : (1.0 - soc) * axis_capacity_Ah;
  }
  bool isConstant() const { return kind == Kind::Constant && arrhenius_K == 0.0; }
  bool dependsOnTemperature() const { return kind == Kind::Table2D || arrhenius_K != 0.0; }

 private:
  struct Points {
    std::vector<double> coeffs, xs, ys, temps_C;
  };
  std::shared_ptr<const Points> pts_ = std::make_shared<const Points>(Points{{0.0}, {}, {}, {}});
};

// Linear interpolation in a table (xs strictly increasing, ys of the same length),
// held flat beyond the ends; a one-point table is a constant.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x);

// A caller's remembered table segment: the index pointAbove found last time (0: none).
// A cell's SOC moves by a hair per evaluation, so it nearly always falls in the same
// segment again; checking that one segment replaces the search. The index found is the
// same either way (the segment i with xs[i-1] <= x < xs[i] is unique), so the result is
// too: the hint saves instructions, never changes a bit.
struct SegmentHint {
  uint32_t i = 0;
};

// The first point above x (std::upper_bound) for xs[0] < x < xs[n-1]: a forward scan on
// a short table (a cell curve: a dozen points, read several times per cell and tick;
// the scan's one mispredicted exit costs less than a binary search's call and its
// guesses), the binary search on a long one (a load profile). Same index either way.
// With a hint: its segment when x lies in it, else the search (and the hint remembers).
inline size_t pointAbove(const double* xs, size_t n, double x, SegmentHint* hint = nullptr) {
  if (hint) {
    const size_t h = hint->i;
    if (h - 1 < n - 1 && xs[h - 1] <= x && x < xs[h]) return h;  // h = 0 wraps: no hint
  }
  constexpr size_t kScanUpTo = 16;
  size_t i = 1;
  if (n > kScanUpTo) {
    i = static_cast<size_t>(std::upper_bound(xs, xs + n, x) - xs);
    // A NaN compares below nothing: upper_bound gives n, one past the table. Kept inside
    // [1, n - 1] as the scan below keeps it (the interpolation is NaN either way).
    i = std::min(std::max<size_t>(i, 1), n - 1);
  } else {
    while (i + 1 < n && !(x < xs[i])) ++i;
  }
  if (hint) hint->i = static_cast<uint32_t>(i);
  return i;
}

// The straight line through points i-1 and i at x: interpolateN's segment, and
// FlatCurve::tableAt's (models/cell/flat_curve.hpp) when x is in its remembered one.
inline double segmentAt(const double* xs, const double* ys, size_t i, double x) {
  const double w = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return ys[i - 1] + w * (ys[i] - ys[i - 1]);
}

// The same over n points of arrays (ys may be one row of a 2-D table).
inline double interpolateN(const double* xs, const double* ys, size_t n, double x, SegmentHint* hint = nullptr) {
  if (n == 1 || x <= xs[0]) return ys[0];
  if (x >= xs[n - 1]) return ys[n - 1];
  return segmentAt(xs, ys, pointAbove(xs, n, x, hint), x);
}

// A table over (x, temperature): `rows` rows of n values (row-major), one per grid
// temperature (temps_C increasing). Each row is interpolated at x, then linearly between
// the two rows around temp_C; held at the grid's first and last row beyond it. The
// optional hints remember the x segment (shared by the rows) and the temperature one.
inline double interpolateGrid(const double* xs, const double* ys, size_t n, const double* temps_C, size_t rows,
                              double x, double temp_C, SegmentHint* x_hint = nullptr,
                              SegmentHint* temp_hint = nullptr) {
  auto row = [&](size_t j) { return interpolateN(xs, ys + j * n, n, x, x_hint); };
  if (rows == 1 || temp_C <= temps_C[0]) return row(0);
  if (temp_C >= temps_C[rows - 1]) return row(rows - 1);
  const size_t j = pointAbove(temps_C, rows, temp_C, temp_hint);
  const double w = (temp_C - temps_C[j - 1]) / (temps_C[j] - temps_C[j - 1]);
  const double lo = row(j - 1);
  return lo + w * (row(j) - lo);
}

// An Arrhenius factor K: R(T) / R(T_ref) = exp(K·(1/T_K - 1/T_ref,K)).
inline double arrheniusFactor(double arrhenius_K, double temp_C, double ref_temp_C) {
  return std::exp(arrhenius_K * (1.0 / (temp_C + kZeroCelsius_K) - 1.0 / (ref_temp_C + kZeroCelsius_K)));
}

}  // namespace packsim
