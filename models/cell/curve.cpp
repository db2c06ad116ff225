#include "models/cell/curve.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "models/cell/flat_curve.hpp"

namespace packsim {

Curve Curve::constant(double value) {
  Curve c;
  c.kind = Kind::Constant;
  c.pts_ = std::make_shared<const Points>(Points{{value}, {}, {}, {}});
  return c;
}

Curve Curve::polynomial(std::vector<double> coeffs_high_first, CurveAxis axis) {
  if (coeffs_high_first.empty()) throw std::invalid_argument("polynomial needs at least one coefficient");
  Curve c;
  c.kind = Kind::Polynomial;
  c.axis = axis;
  c.pts_ = std::make_shared<const Points>(Points{std::move(coeffs_high_first), {}, {}, {}});
  return c;
}

namespace {

void requireIncreasing(const std::vector<double>& v, const char* what) {
  for (size_t i = 1; i < v.size(); ++i)
    if (!(v[i] > v[i - 1])) throw std::invalid_argument(std::string(what) + " values must increase strictly");
}

}  // namespace

Curve Curve::table(std::vector<double> xs, std::vector<double> ys, CurveAxis axis) {
  if (xs.size() != ys.size() || xs.size() < 2)
    throw std::invalid_argument("table needs x and y of equal length >= 2");
  requireIncreasing(xs, "table x");
  Curve c;
  c.kind = Kind::Table;
  c.axis = axis;
  c.pts_ = std::make_shared<const Points>(Points{{}, std::move(xs), std::move(ys), {}});
  return c;
}

Curve Curve::table2d(std::vector<double> xs, std::vector<double> temps_C, const std::vector<std::vector<double>>& rows,
                     CurveAxis axis) {
  if (xs.size() < 2 || temps_C.empty() || rows.size() != temps_C.size())
    throw std::invalid_argument("2-D table needs x (>= 2 values) and one row of y per temperature");
  requireIncreasing(xs, "table x");
  requireIncreasing(temps_C, "table temp_C");
  Curve c;
  c.kind = Kind::Table2D;
  c.axis = axis;
  std::vector<double> ys;
  for (const auto& row : rows) {
    if (row.size() != xs.size()) throw std::invalid_argument("2-D table: every row needs as many values as x");
    ys.insert(ys.end(), row.begin(), row.end());
  }
  c.pts_ = std::make_shared<const Points>(Points{{}, std::move(xs), std::move(ys), std::move(temps_C)});
  return c;
}

Curve Curve::withArrhenius(double k, double ref_C) const {
  if (kind == Kind::Table2D) throw std::invalid_argument("a 2-D table carries its temperature dependence itself");
  Curve c = *this;
  c.arrhenius_K = k;
  c.ref_temp_C = ref_C;
  return c;
}

double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  return interpolateN(xs.data(), ys.data(), xs.size(), x);
}

double Curve::at(double x) const {
  const std::vector<double>& coeffs = pts_->coeffs;
  switch (kind) {
    case Kind::Constant:
      return coeffs[0];
    case Kind::Polynomial: {
      double y = 0.0;  // Horner
      for (double c : coeffs) y = y * x + c;
      return y;
    }
    case Kind::Table:
      return interpolate(pts_->xs, pts_->ys, x);
    case Kind::Table2D:
      return at(x, kReferenceTemp_C);
  }
  return 0.0;
}

double Curve::at(double x, double temp_C) const {
  if (kind == Kind::Table2D) {
    const Points& p = *pts_;
    return interpolateGrid(p.xs.data(), p.ys.data(), p.xs.size(), p.temps_C.data(), p.temps_C.size(), x, temp_C);
  }
  const double y = at(x);
  if (arrhenius_K == 0.0) return y;
  return y * arrheniusFactor(arrhenius_K, temp_C, ref_temp_C);
}

double Curve::eval(double soc, double axis_capacity_Ah) const { return eval(soc, axis_capacity_Ah, kReferenceTemp_C); }

double Curve::eval(double soc, double axis_capacity_Ah, double temp_C) const {
  if (kind == Kind::Constant && arrhenius_K == 0.0) return pts_->coeffs[0];
  if (!dependsOnTemperature()) return at(axisValue(soc, axis_capacity_Ah));  // the 1-D path, as without T
  return at(axisValue(soc, axis_capacity_Ah), temp_C);
}

double FlatCurve::evalOther(double soc, double axis_capacity_Ah, double temp_C, CurveHint& hint) const {
  if (kind == Curve::Kind::Constant && arrhenius_K == 0.0) return coeffs[0];
  const double x = axisX(soc, axis_capacity_Ah);
  if (kind == Curve::Kind::Table2D)
    return interpolateGrid(xs, ys, n, temps_C, rows, x, temp_C, &hint.x, &hint.temp);
  return timesArrhenius(at(x, hint.x), temp_C);
}

}  // namespace packsim
