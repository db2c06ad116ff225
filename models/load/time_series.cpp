#include "models/load/time_series.hpp"

#include <algorithm>

namespace packsim {

double TimeSeries::at(double t) const {
  if (t_s.size() == 1 || t <= t_s.front()) return value.front();
  if (t >= t_s.back()) return value.back();
  const size_t i = static_cast<size_t>(std::upper_bound(t_s.begin(), t_s.end(), t) - t_s.begin());
  const double w = (t - t_s[i - 1]) / (t_s[i] - t_s[i - 1]);
  return value[i - 1] + w * (value[i] - value[i - 1]);
}

}  // namespace packsim
