#include "core/balance/balance_analytic.hpp"

namespace packsim {

double socAtOcv(const CellParams& cell, double v) {
  double lo = 0.0, hi = 1.0;
  if (v <= ecm::ocv(cell, lo)) return lo;
  if (v >= ecm::ocv(cell, hi)) return hi;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ecm::ocv(cell, mid) < v ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double constantCurrentHours(double delta_Ah, double cell_V, double branch_ohm) {
  return delta_Ah / (cell_V / branch_ohm);
}

double ocvDroopHours(const CellParams& cell, double group_Ah, double soc_low, double soc_high, double branch_ohm) {
  // Composite Simpson's rule on 2000 intervals: the OCV tables are piecewise linear,
  // so the error is far below the 1e-4 relative the callers need.
  const int n = 2000;
  const double h = (soc_high - soc_low) / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w / ecm::ocv(cell, soc_low + i * h);
  }
  return branch_ohm * group_Ah * sum * h / 3.0;
}

}  // namespace packsim
