#include "models/sensors/adc.hpp"

#include <algorithm>
#include <cmath>

namespace packsim {

double standardNormal(Rng& rng) {
  if (rng.hasSpare_) {
    rng.hasSpare_ = false;
    return rng.spare_;
  }
  constexpr double kTwoPi = 6.283185307179586;
  const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
  const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double a = kTwoPi * u2;
  rng.spare_ = r * std::sin(a);
  rng.hasSpare_ = true;
  return r * std::cos(a);
}

int64_t AdcChannel::convert(double x, Rng& rng) const {
  double v = x * (1.0 + gain_error) + offset;
  if (noise_rms > 0.0) v += noise_rms * standardNormal(rng);
  const double code = std::nearbyint(v / lsb);
  if (!(code > static_cast<double>(code_min))) return code_min;  // also catches NaN
  if (code > static_cast<double>(code_max)) return code_max;
  return static_cast<int64_t>(code);
}

}  // namespace packsim
