// Analog-to-digital conversion shared by the sensor models: an ideal converter with
// gain and offset error and Gaussian noise, rounding to the nearest code and
// saturating at the rails.
//
//   code = clamp(round((x·(1 + gain_error) + offset + noise) / lsb), code_min, code_max)
//   noise ~ N(0, noise_rms)
#pragma once
#include <cstdint>

#include "models/random/random.hpp"  // Rng, standardNormal
#include "models/sensors/round_even.hpp"

namespace packsim {

struct AdcChannel {
  double lsb = 1.0;          // input units per code
  double gain_error = 0.0;   // relative: 0.055 reads 5.5 % high
  double offset = 0.0;       // input units
  double noise_rms = 0.0;    // input units
  int64_t code_min = 0;
  int64_t code_max = 65535;

  int64_t convert(double x, Rng& rng) const { return convertWith(gain_error, offset, x, rng); }
  // The same conversion with this gain error and offset instead of the channel's own
  // (a monitor input's: the part's plus the channel's drawn and injected errors), without
  // copying the channel. Inline: several conversions per tick and cell.
  int64_t convertWith(double gainError, double offsetIn, double x, Rng& rng) const {
    double v = x * (1.0 + gainError) + offsetIn;
    if (noise_rms > 0.0) v += noise_rms * standardNormal(rng);
    const double code = roundHalfEven(v / lsb);  // std::nearbyint, inline (round_even.hpp)
    if (!(code > static_cast<double>(code_min))) return code_min;  // also catches NaN
    if (code > static_cast<double>(code_max)) return code_max;
    return static_cast<int64_t>(code);
  }
};

}  // namespace packsim
