#include "models/vehicle/clear_sky.hpp"

#include <cmath>

namespace packsim {

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
}

double solarCosZenith(const SunPosition& w, double hour) {
  const double decl = 23.45 * kDeg * std::sin(360.0 * kDeg * (284.0 + w.day_of_year) / 365.0);
  const double omega = 15.0 * kDeg * (std::fmod(hour, 24.0) - 12.0);
  const double phi = w.latitude_deg * kDeg;
  return std::sin(phi) * std::sin(decl) + std::cos(phi) * std::cos(decl) * std::cos(omega);
}

double clearSkyIrradiance_W_per_m2(const SunPosition& w, double hour) {
  const double cz = solarCosZenith(w, hour);
  if (cz <= 0.0) return 0.0;
  const double airMass = 1.0 / cz;
  const double direct = 1353.0 * std::pow(0.7, std::pow(airMass, 0.678));
  return 1.1 * direct * cz;
}

double SolarArray::power_W(double t_s) const {
  if (area_m2 <= 0.0) return 0.0;
  if (!table.empty())
    return area_m2 * efficiency * mppt_efficiency * table.value_W_per_m2(t_s, start_solar_hour + t_s / 3600.0);
  return area_m2 * efficiency * mppt_efficiency * clearSkyIrradiance_W_per_m2(where, start_solar_hour + t_s / 3600.0);
}

}  // namespace packsim
