#include "core/scenario/irradiance_csv.hpp"

#include <algorithm>

#include "core/scenario/csv_table.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/scenario/value_ranges.hpp"

namespace packsim {

using namespace csv;

namespace {
// The solar constant is 1361 W/m²; at the ground, cloud-edge enhancement briefly reaches
// ~1500 W/m²: 2000 leaves room and still catches a table in the wrong unit (kW/m² x 1000).
constexpr double kMaxIrradiance_W_per_m2 = 2000.0;
}  // namespace

IrradianceTable readIrradianceCsv(const std::string& path) {
  TableReader csv(path);
  if (!csv.readHeader())
    throw ScenarioError(path, std::max(csv.line(), 1), 1, "", "empty CSV: expected a header such as 'time_s,ghi_W_per_m2'");
  IrradianceTable t;
  const int headerLine = csv.line();
  const auto ts = csv.column("time_s"), hour = csv.column("solar_hour");
  const auto ghi = csv.column("ghi_W_per_m2"), poa = csv.column("poa_W_per_m2");
  if (!ts && !hour) throw csv.missing("'time_s' or 'solar_hour'", "time_s");
  if (ts && hour) throw ScenarioError(path, headerLine, 1, "solar_hour", "give 'time_s' or 'solar_hour', not both");
  if (!ghi && !poa) throw csv.missing("'ghi_W_per_m2' or 'poa_W_per_m2'", "ghi_W_per_m2");
  if (ghi && poa) throw ScenarioError(path, headerLine, 1, "poa_W_per_m2", "give 'ghi_W_per_m2' or 'poa_W_per_m2', not both");
  t.clock = ts ? IrradianceTable::Clock::RunTime : IrradianceTable::Clock::TimeOfDay;
  t.plane_of_array = poa.has_value();
  const size_t timeCol = ts ? *ts : *hour;
  const size_t irrCol = ghi ? *ghi : *poa;
  const bool hours = t.clock == IrradianceTable::Clock::TimeOfDay;
  int lastLine = 0;
  while (csv.nextRow()) {
    const double x = hours ? csv.value(timeCol, 0.0, 24.0, "h") : csv.value(timeCol, 0.0, limits::kMaxTime_s, "s");
    if (t.at.empty() && x != 0.0)
      throw csv.errorAt(timeCol, hours ? "the first row must be at 0 h (the table spans a day, 0 to 24 h)"
                                       : "the first row must be at 0 s (the run's start)");
    if (!t.at.empty() && !(x > t.at.back()))
      throw csv.errorAt(timeCol, "must increase strictly: " + csv.cell(timeCol).text + " after the previous row's");
    t.at.push_back(x);
    t.irradiance_W_per_m2.push_back(csv.value(irrCol, 0.0, kMaxIrradiance_W_per_m2, "W/m2"));
    lastLine = csv.line();
  }
  if (t.at.size() < 2)
    throw ScenarioError(path, std::max(csv.line(), 1), 1, "",
                        "an irradiance table needs at least 2 rows, got " + std::to_string(t.at.size()));
  if (hours && t.at.back() != 24.0)
    throw ScenarioError(path, lastLine, 1, csv.name(timeCol),
                        "the last row must be at 24 h (the table spans a day, 0 to 24 h, repeated every day)");
  if (hours && t.irradiance_W_per_m2.back() != t.irradiance_W_per_m2.front())
    throw ScenarioError(path, lastLine, 1, csv.name(irrCol),
                        "the 24 h row must equal the 0 h row (the same day repeated: midnight is both)");
  return t;
}

}  // namespace packsim
