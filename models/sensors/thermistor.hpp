// NTC thermistor (beta model) at the bottom of a divider from the ADC reference,
// read ratiometrically:
//
//   R(T) = R25 · exp(β · (1/T - 1/298.15 K))
//   code = full_scale · R / (R_pullup + R)
//
// An open sensor reads full scale, a shorted one reads 0: the firmware flags both.
#pragma once
#include "models/sensors/adc.hpp"

namespace packsim {

struct Thermistor {
  double r25_ohm = 10000.0;
  double beta_K = 3435.0;
  double pullup_ohm = 10000.0;
  int bits = 12;
  double noise_codes_rms = 0.0;

  double resistance_ohm(double temp_C) const;
  int64_t fullScaleCode() const { return (int64_t{1} << bits) - 1; }
  // The divider's noiseless code (unrounded) at temp_C, and a conversion of it: code(T)
  // is codeOf(idealCode(T)), so a caller may keep idealCode for an unchanged T.
  double idealCode(double temp_C) const;
  // Its inverse: the temperature (K) whose divider code is `code`, 0 < code < full scale.
  double temperatureAt_K(double code) const;
  // Inline: the monitor models convert their thermistor inputs several times per tick.
  int64_t codeOf(double ideal_code, Rng& rng) const {
    AdcChannel adc;
    adc.lsb = 1.0;
    adc.noise_rms = noise_codes_rms;
    adc.code_min = 0;
    adc.code_max = fullScaleCode();
    return adc.convert(ideal_code, rng);
  }
  int64_t code(double temp_C, Rng& rng) const { return codeOf(idealCode(temp_C), rng); }
};

}  // namespace packsim
