// Irradiance from a table instead of the clear-sky formula (load.sun.irradiance_csv;
// docs/vehicle.md, "Irradiance from a table"): rows of (time, irradiance), linear
// between rows. The time is either the run's clock (time_s from t = 0; the table ends
// the run at its last row) or the solar time of day (solar_hour, rows from 0 to 24 h,
// the same day repeated). The irradiance is either global horizontal (what falls on
// the flat array) or plane-of-array (measured in the array's own plane); both are the
// irradiance G on the array, P_array = A·η_pv·η_mppt·G.
#pragma once
#include <vector>

namespace packsim {

struct IrradianceTable {
  enum class Clock { RunTime, TimeOfDay };
  Clock clock = Clock::RunTime;
  bool plane_of_array = false;       // false: global horizontal
  std::vector<double> at;            // time_s, or solar hour; strictly increasing
  std::vector<double> irradiance_W_per_m2;

  bool empty() const { return at.empty(); }
  // G at run time t_s, the solar time of day then being solar_hour (linear between rows;
  // a run-time table holds its last row past its end, where the run ends: end_s).
  double value_W_per_m2(double t_s, double solar_hour) const;
  // The run time the table ends (a time-of-day table: never).
  double end_s() const;
};

}  // namespace packsim
