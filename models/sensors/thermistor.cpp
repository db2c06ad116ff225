#include "models/sensors/thermistor.hpp"

#include <cmath>

namespace packsim {

double Thermistor::resistance_ohm(double temp_C) const {
  return r25_ohm * std::exp(beta_K * (1.0 / (temp_C + 273.15) - 1.0 / 298.15));
}

int64_t Thermistor::code(double temp_C, Rng& rng) const {
  const double r = resistance_ohm(temp_C);
  const double fs = static_cast<double>(fullScaleCode());
  AdcChannel adc;
  adc.lsb = 1.0;
  adc.noise_rms = noise_codes_rms;
  adc.code_min = 0;
  adc.code_max = fullScaleCode();
  return adc.convert(fs * r / (pullup_ohm + r), rng);
}

}  // namespace packsim
