#include "models/load/time_series.hpp"

#include "models/cell/curve.hpp"

namespace packsim {

double TimeSeries::at(double t) const { return interpolate(t_s, value, t); }

}  // namespace packsim
