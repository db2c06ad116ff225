// Irradiance from a CSV table (load.sun.irradiance_csv; docs/vehicle.md, "Irradiance
// from a table"): a header row, then one row per time. Columns, by name:
//
//   time_s or solar_hour        the run's clock from t = 0 (first row 0), or the solar
//                               time of day (rows from 0 to 24 h, repeated every day)
//   ghi_W_per_m2 or poa_W_per_m2  global horizontal irradiance (on the flat array), or
//                               plane-of-array irradiance (measured in the array's plane)
//
// Times strictly increasing; irradiance in [0, 2000] W/m². Errors name the file, the
// line, the column and the allowed range.
#pragma once
#include <string>

#include "models/vehicle/irradiance_table.hpp"

namespace packsim {

IrradianceTable readIrradianceCsv(const std::string& path);

}  // namespace packsim
