// A scalar function of one cell variable, given as a polynomial or a table.
//
//   polynomial: y = c[0]·x^n + c[1]·x^(n-1) + … + c[n]   (highest power first, as
//               numpy.polyval and spreadsheet trendlines write it)
//   table:      linear interpolation between (x[i], y[i]); held flat beyond the ends
//
// The axis says what x is: state of charge (0…1) or capacity discharged in Ah
// (x = (1 - SOC)·capacity_Ah), the form many bench fits use.
#pragma once
#include <string>
#include <vector>

namespace packsim {

enum class CurveAxis { Soc, Discharged_Ah };

struct Curve {
  enum class Kind { Constant, Polynomial, Table };
  Kind kind = Kind::Constant;
  CurveAxis axis = CurveAxis::Soc;
  std::vector<double> coeffs;  // polynomial, highest power first; constant: one value
  std::vector<double> xs, ys;  // table, xs strictly increasing

  static Curve constant(double value);
  static Curve polynomial(std::vector<double> coeffs_high_first, CurveAxis axis = CurveAxis::Soc);
  static Curve table(std::vector<double> xs, std::vector<double> ys, CurveAxis axis = CurveAxis::Soc);

  double eval(double soc, double capacity_Ah) const;
  double at(double x) const;  // evaluated on the curve's own axis
  bool isConstant() const { return kind == Kind::Constant; }
};

// Linear interpolation in a table (xs strictly increasing, ys of the same length),
// held flat beyond the ends; a one-point table is a constant.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x);

}  // namespace packsim
