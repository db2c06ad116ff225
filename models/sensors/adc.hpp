// Analog-to-digital conversion shared by the sensor models: an ideal converter with
// gain and offset error and Gaussian noise, rounding to the nearest code and
// saturating at the rails.
//
//   code = clamp(round((x·(1 + gain_error) + offset + noise) / lsb), code_min, code_max)
//   noise ~ N(0, noise_rms)
#pragma once
#include <cstdint>

#include "models/random/random.hpp"  // Rng, standardNormal

namespace packsim {

struct AdcChannel {
  double lsb = 1.0;          // input units per code
  double gain_error = 0.0;   // relative: 0.055 reads 5.5 % high
  double offset = 0.0;       // input units
  double noise_rms = 0.0;    // input units
  int64_t code_min = 0;
  int64_t code_max = 65535;

  int64_t convert(double x, Rng& rng) const;
};

}  // namespace packsim
