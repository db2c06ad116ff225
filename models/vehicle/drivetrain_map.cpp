#include "models/vehicle/drivetrain_map.hpp"

#include <algorithm>

namespace packsim {

namespace {
// The cell [lo, lo+1] holding x, and x's fraction across it (clamped to the axis' ends).
void locate(const std::vector<double>& axis, double x, size_t& lo, double& f) {
  if (x <= axis.front()) {
    lo = 0;
    f = 0.0;
    return;
  }
  if (x >= axis.back()) {
    lo = axis.size() - 2;
    f = 1.0;
    return;
  }
  lo = static_cast<size_t>(std::upper_bound(axis.begin(), axis.end(), x) - axis.begin()) - 1;
  f = (x - axis[lo]) / (axis[lo + 1] - axis[lo]);
}
}  // namespace

double DrivetrainMap::at(double v, double torque) const {
  size_t i = 0, j = 0;
  double fv = 0.0, ft = 0.0;
  locate(speed_m_per_s, v, i, fv);
  locate(torque_Nm, torque, j, ft);
  const size_t n = torque_Nm.size();
  const double e00 = efficiency[i * n + j], e01 = efficiency[i * n + j + 1];
  const double e10 = efficiency[(i + 1) * n + j], e11 = efficiency[(i + 1) * n + j + 1];
  return (1.0 - fv) * ((1.0 - ft) * e00 + ft * e01) + fv * ((1.0 - ft) * e10 + ft * e11);
}

}  // namespace packsim
