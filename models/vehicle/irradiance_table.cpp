#include "models/vehicle/irradiance_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace packsim {

double IrradianceTable::value_W_per_m2(double t_s, double solar_hour) const {
  if (at.empty()) return 0.0;
  const double x = clock == Clock::RunTime ? t_s : solar_hour - 24.0 * std::floor(solar_hour / 24.0);
  if (x <= at.front()) return irradiance_W_per_m2.front();
  if (x >= at.back()) return irradiance_W_per_m2.back();
  const size_t hi = static_cast<size_t>(std::upper_bound(at.begin(), at.end(), x) - at.begin());
  const size_t lo = hi - 1;
  const double f = (x - at[lo]) / (at[hi] - at[lo]);
  return irradiance_W_per_m2[lo] + f * (irradiance_W_per_m2[hi] - irradiance_W_per_m2[lo]);
}

double IrradianceTable::end_s() const {
  if (at.empty() || clock == Clock::TimeOfDay) return std::numeric_limits<double>::infinity();
  return at.back();
}

}  // namespace packsim
