#include "models/cell/curve.hpp"

#include <algorithm>
#include <stdexcept>

namespace packsim {

Curve Curve::constant(double value) {
  Curve c;
  c.kind = Kind::Constant;
  c.coeffs = {value};
  return c;
}

Curve Curve::polynomial(std::vector<double> coeffs_high_first, CurveAxis axis) {
  if (coeffs_high_first.empty()) throw std::invalid_argument("polynomial needs at least one coefficient");
  Curve c;
  c.kind = Kind::Polynomial;
  c.axis = axis;
  c.coeffs = std::move(coeffs_high_first);
  return c;
}

Curve Curve::table(std::vector<double> xs, std::vector<double> ys, CurveAxis axis) {
  if (xs.size() != ys.size() || xs.size() < 2)
    throw std::invalid_argument("table needs x and y of equal length >= 2");
  for (size_t i = 1; i < xs.size(); ++i)
    if (!(xs[i] > xs[i - 1])) throw std::invalid_argument("table x values must increase strictly");
  Curve c;
  c.kind = Kind::Table;
  c.axis = axis;
  c.xs = std::move(xs);
  c.ys = std::move(ys);
  return c;
}

double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
  if (xs.size() == 1 || x <= xs.front()) return ys.front();
  if (x >= xs.back()) return ys.back();
  const auto it = std::upper_bound(xs.begin(), xs.end(), x);
  const size_t i = static_cast<size_t>(it - xs.begin());
  const double w = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return ys[i - 1] + w * (ys[i] - ys[i - 1]);
}

double Curve::at(double x) const {
  switch (kind) {
    case Kind::Constant:
      return coeffs[0];
    case Kind::Polynomial: {
      double y = 0.0;  // Horner
      for (double c : coeffs) y = y * x + c;
      return y;
    }
    case Kind::Table:
      return interpolate(xs, ys, x);
  }
  return 0.0;
}

double Curve::eval(double soc, double capacity_Ah) const {
  if (kind == Kind::Constant) return coeffs[0];
  return at(axis == CurveAxis::Soc ? soc : (1.0 - soc) * capacity_Ah);
}

}  // namespace packsim
