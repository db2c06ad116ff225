// A scalar that follows (time_s, value) points with linear interpolation, held flat
// before the first and after the last point (e.g. ambient temperature over a race).
#pragma once
#include <vector>

namespace packsim {

struct TimeSeries {
  std::vector<double> t_s;
  std::vector<double> value;

  static TimeSeries constant(double v) { return TimeSeries{{0.0}, {v}}; }
  double at(double t) const;
};

}  // namespace packsim
