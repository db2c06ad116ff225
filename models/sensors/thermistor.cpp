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

double Thermistor::temperatureAt_K(double code) const {
  const double ratio = code / static_cast<double>(fullScaleCode());
  const double r = pullup_ohm * ratio / (1.0 - ratio);
  return 1.0 / (1.0 / 298.15 + std::log(r / r25_ohm) / beta_K);
}

}  // namespace packsim
