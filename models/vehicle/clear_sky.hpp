// Clear-sky irradiance on a horizontal surface from latitude, day of the year and
// solar time (docs/vehicle.md, "The sun"):
//
//   declination   δ = 23.45° · sin(360° · (284 + n) / 365)          (Cooper, 1969)
//   hour angle    ω = 15° · (solar hour − 12)
//   zenith        cos z = sin φ · sin δ + cos φ · cos δ · cos ω
//   air mass      AM = 1 / cos z
//   direct beam   I_D = 1353 W/m² · 0.7^(AM^0.678)                  (Meinel & Meinel, 1976)
//   global        G_h = 1.1 · I_D · cos z   (diffuse light ~10 % of the beam)
//
// Zero when the sun is below the horizon.
#pragma once
#include "models/vehicle/irradiance_table.hpp"

namespace packsim {

struct SunPosition {
  double latitude_deg = 0.0;
  int day_of_year = 172;  // 1..366
};

double solarCosZenith(const SunPosition& where, double solar_hour);
double clearSkyIrradiance_W_per_m2(const SunPosition& where, double solar_hour);

// A flat array: area × cell efficiency × MPPT efficiency × irradiance [W into the bus];
// the irradiance from the clear-sky formula, or from a table when one is given.
struct SolarArray {
  double area_m2 = 0.0;
  double efficiency = 0.0;       // module efficiency at the irradiance (STC)
  double mppt_efficiency = 1.0;  // tracker / converter
  SunPosition where;
  double start_solar_hour = 12.0;  // solar time at t = 0
  IrradianceTable table;           // empty: the clear-sky formula at `where`
  double power_W(double t_s) const;
};

}  // namespace packsim
