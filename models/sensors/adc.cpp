#include "models/sensors/adc.hpp"

#include <algorithm>
#include <cmath>

#include "models/sensors/round_even.hpp"

namespace packsim {

int64_t AdcChannel::convert(double x, Rng& rng) const {
  double v = x * (1.0 + gain_error) + offset;
  if (noise_rms > 0.0) v += noise_rms * standardNormal(rng);
  const double code = roundHalfEven(v / lsb);  // std::nearbyint, inline (round_even.hpp)
  if (!(code > static_cast<double>(code_min))) return code_min;  // also catches NaN
  if (code > static_cast<double>(code_max)) return code_max;
  return static_cast<int64_t>(code);
}

}  // namespace packsim
