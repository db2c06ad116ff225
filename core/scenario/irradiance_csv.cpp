#include "core/scenario/irradiance_csv.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "core/scenario/csv_text.hpp"
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
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ScenarioError(path, 0, 0, "", "not a CSV file (it is a folder or a device)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ScenarioError(path, 0, 0, "", "cannot open CSV file");
  IrradianceTable t;
  std::string line;
  int lineNo = 0;
  char sep = 0;
  std::vector<std::string> names;
  std::optional<size_t> timeCol, irrCol;
  auto column = [&](const char* name) -> std::optional<size_t> {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) return std::nullopt;
    return static_cast<size_t>(it - names.begin());
  };
  auto missing = [&](const std::string& what, const std::string& expected) {
    const std::string near = closestMatch(expected, names);
    return ScenarioError(path, lineNo, 1, "",
                         "no " + what + " column in the header (columns as read: " + joined(names) + ")" +
                             (near.empty() ? "" : "; did you mean '" + near + "'?"));
  };
  int lastLine = 0;
  while (nextDataLine(in, line, lineNo)) {
    if (sep == 0) {  // the header row
      sep = separatorOf(line);
      for (const Cell& c : splitRow(line, sep)) names.push_back(unquote(c.text));
      const auto ts = column("time_s"), hour = column("solar_hour");
      const auto ghi = column("ghi_W_per_m2"), poa = column("poa_W_per_m2");
      if (!ts && !hour) throw missing("'time_s' or 'solar_hour'", "time_s");
      if (ts && hour) throw ScenarioError(path, lineNo, 1, "solar_hour", "give 'time_s' or 'solar_hour', not both");
      if (!ghi && !poa) throw missing("'ghi_W_per_m2' or 'poa_W_per_m2'", "ghi_W_per_m2");
      if (ghi && poa) throw ScenarioError(path, lineNo, 1, "poa_W_per_m2", "give 'ghi_W_per_m2' or 'poa_W_per_m2', not both");
      t.clock = ts ? IrradianceTable::Clock::RunTime : IrradianceTable::Clock::TimeOfDay;
      t.plane_of_array = poa.has_value();
      timeCol = ts ? ts : hour;
      irrCol = ghi ? ghi : poa;
      continue;
    }
    const std::vector<Cell> cells = splitRow(line, sep);
    if (cells.size() != names.size())
      throw ScenarioError(path, lineNo, cells.size() > names.size() ? cells[names.size()].column : 1, "",
                          "expected " + std::to_string(names.size()) + " columns (as the header: " + joined(names) +
                              "), got " + std::to_string(cells.size()));
    auto value = [&](size_t col, double lo, double hi, const char* unit) {
      const Cell& c = cells[col];
      std::string text = unquote(c.text);
      if (sep == ';') std::replace(text.begin(), text.end(), ',', '.');
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw ScenarioError(path, lineNo, c.column, names[col], "'" + c.text + "' is not a finite number");
      if (v < lo || v > hi) {
        std::ostringstream os;
        os << "'" << c.text << "' is out of range; allowed [" << lo << ", " << hi << "] " << unit;
        throw ScenarioError(path, lineNo, c.column, names[col], os.str());
      }
      return v;
    };
    const bool hours = t.clock == IrradianceTable::Clock::TimeOfDay;
    const double x = hours ? value(*timeCol, 0.0, 24.0, "h") : value(*timeCol, 0.0, limits::kMaxTime_s, "s");
    const Cell& xc = cells[*timeCol];
    if (t.at.empty() && x != 0.0)
      throw ScenarioError(path, lineNo, xc.column, names[*timeCol],
                          hours ? "the first row must be at 0 h (the table spans a day, 0 to 24 h)"
                                : "the first row must be at 0 s (the run's start)");
    if (!t.at.empty() && !(x > t.at.back()))
      throw ScenarioError(path, lineNo, xc.column, names[*timeCol],
                          "must increase strictly: " + xc.text + " after the previous row's");
    t.at.push_back(x);
    t.irradiance_W_per_m2.push_back(value(*irrCol, 0.0, kMaxIrradiance_W_per_m2, "W/m2"));
    lastLine = lineNo;
  }
  if (sep == 0)
    throw ScenarioError(path, std::max(lineNo, 1), 1, "", "empty CSV: expected a header such as 'time_s,ghi_W_per_m2'");
  if (t.at.size() < 2)
    throw ScenarioError(path, std::max(lineNo, 1), 1, "",
                        "an irradiance table needs at least 2 rows, got " + std::to_string(t.at.size()));
  if (t.clock == IrradianceTable::Clock::TimeOfDay && t.at.back() != 24.0)
    throw ScenarioError(path, lastLine, 1, names[*timeCol],
                        "the last row must be at 24 h (the table spans a day, 0 to 24 h, repeated every day)");
  if (t.clock == IrradianceTable::Clock::TimeOfDay && t.irradiance_W_per_m2.back() != t.irradiance_W_per_m2.front())
    throw ScenarioError(path, lastLine, 1, names[*irrCol],
                        "the 24 h row must equal the 0 h row (the same day repeated: midnight is both)");
  return t;
}

}  // namespace packsim
