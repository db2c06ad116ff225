#include "models/sensors/thermistor.hpp"

#include <cmath>

namespace packsim {

double Thermistor::resistance_ohm(double temp_C) const {
  return r25_ohm * std::exp(beta_K * (1.0 / (temp_C + 273.15) - 1.0 / 298.15));
}

double Thermistor::idealCode(double temp_C) const {
  const double r = resistance_ohm(temp_C);
  return static_cast<double>(fullScaleCode()) * r / (pullup_ohm + r);
}

int64_t Thermistor::codeOf(double ideal_code, Rng& rng) const {
  AdcChannel adc;
  adc.lsb = 1.0;
  adc.noise_rms = noise_codes_rms;
  adc.code_min = 0;
  adc.code_max = fullScaleCode();
  return adc.convert(ideal_code, rng);
}

}  // namespace packsim
