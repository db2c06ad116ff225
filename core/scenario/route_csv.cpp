#include "core/scenario/route_csv.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "core/scenario/csv_text.hpp"
#include "core/scenario/scenario_error.hpp"

namespace packsim {

using namespace csv;

namespace {

// The ranges of the route keys (core/scenario/load_vehicle.cpp) and of the wind.
constexpr double kMaxRoute_km = 1.0e5;          // 100,000 km
constexpr double kMaxGrade_percent = 100.0;     // ±45°
constexpr double kMaxSpeed_kmh = 360.0;
constexpr double kMaxWind_kmh = 400.0;          // the strongest gusts measured are ~400 km/h
constexpr double kMinElevation_m = -500.0;      // the Dead Sea shore is at −430 m
constexpr double kMaxElevation_m = 9000.0;
constexpr double kPi = 3.14159265358979323846;

struct Row {
  int line = 0;
  double distance_m = 0.0, grade = 0.0, elevation_m = 0.0, speed_m_per_s = 0.0, headwind_m_per_s = 0.0;
};

}  // namespace

std::vector<RouteSegment> readRouteCsv(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw ScenarioError(path, 0, 0, "", "not a CSV file (it is a folder or a device)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ScenarioError(path, 0, 0, "", "cannot open CSV file");
  std::string line;
  int lineNo = 0;
  char sep = 0;
  std::vector<std::string> names;
  std::optional<size_t> distKm, distM, grade, elev, speed, headwind, wind, windFrom, heading;
  std::vector<Row> rows;
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
  while (nextDataLine(in, line, lineNo)) {
    if (sep == 0) {  // the header row
      sep = separatorOf(line);
      for (const Cell& c : splitRow(line, sep)) names.push_back(unquote(c.text));
      distKm = column("distance_km");
      distM = column("distance_m");
      grade = column("grade_percent");
      elev = column("elevation_m");
      speed = column("speed_kmh");
      headwind = column("headwind_kmh");
      wind = column("wind_kmh");
      windFrom = column("wind_from_deg");
      heading = column("heading_deg");
      if (!distKm && !distM) throw missing("'distance_km' or 'distance_m'", "distance_km");
      if (distKm && distM) throw ScenarioError(path, lineNo, 1, "distance_m", "give 'distance_km' or 'distance_m', not both");
      if (!grade && !elev) throw missing("'grade_percent' or 'elevation_m'", "grade_percent");
      if (grade && elev) throw ScenarioError(path, lineNo, 1, "elevation_m", "give 'grade_percent' or 'elevation_m', not both");
      if (!speed) throw missing("'speed_kmh'", "speed_kmh");
      const int windCols = (wind ? 1 : 0) + (windFrom ? 1 : 0) + (heading ? 1 : 0);
      if (windCols != 0 && windCols != 3)
        throw ScenarioError(path, lineNo, 1, wind ? (windFrom ? "heading_deg" : "wind_from_deg") : "wind_kmh",
                            "the wind by direction needs all of 'wind_kmh', 'wind_from_deg' and 'heading_deg'");
      if (windCols == 3 && headwind)
        throw ScenarioError(path, lineNo, 1, "headwind_kmh", "give 'headwind_kmh' or the wind by direction, not both");
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
    Row r;
    r.line = lineNo;
    const size_t dcol = distKm ? *distKm : *distM;
    r.distance_m = distKm ? value(dcol, 0.0, kMaxRoute_km, "km") * 1000.0 : value(dcol, 0.0, kMaxRoute_km * 1000.0, "m");
    if (rows.empty() && r.distance_m != 0.0)
      throw ScenarioError(path, lineNo, cells[dcol].column, names[dcol], "the first point must be at distance 0");
    if (!rows.empty() && !(r.distance_m > rows.back().distance_m)) {
      std::ostringstream os;
      os << "distance must increase strictly: " << cells[dcol].text << " after the previous row's";
      throw ScenarioError(path, lineNo, cells[dcol].column, names[dcol], os.str());
    }
    if (grade) r.grade = value(*grade, -kMaxGrade_percent, kMaxGrade_percent, "%") / 100.0;
    if (elev) r.elevation_m = value(*elev, kMinElevation_m, kMaxElevation_m, "m");
    // The speed of the last row is not used (the route ends there), but must still be valid.
    const Cell& sc = cells[*speed];
    r.speed_m_per_s = value(*speed, 0.0, kMaxSpeed_kmh, "km/h") / 3.6;
    if (!(r.speed_m_per_s > 0.0))
      throw ScenarioError(path, lineNo, sc.column, names[*speed], "'" + sc.text + "' is out of range; allowed (0, 360] km/h");
    if (headwind) r.headwind_m_per_s = value(*headwind, -kMaxWind_kmh, kMaxWind_kmh, "km/h") / 3.6;
    if (wind) {
      const double w = value(*wind, 0.0, kMaxWind_kmh, "km/h") / 3.6;
      const double from = value(*windFrom, 0.0, 360.0, "degrees");
      const double head = value(*heading, 0.0, 360.0, "degrees");
      r.headwind_m_per_s = w * std::cos((from - head) * kPi / 180.0);
    }
    if (elev && !rows.empty()) {  // the grade of the segment that ends here
      Row& prev = rows.back();
      prev.grade = (r.elevation_m - prev.elevation_m) / (r.distance_m - prev.distance_m);
      if (std::fabs(prev.grade) > kMaxGrade_percent / 100.0) {
        std::ostringstream os;
        os << "the elevation from line " << prev.line << " gives a grade of " << prev.grade * 100.0
           << " %; allowed [-100, 100] %";
        throw ScenarioError(path, lineNo, cells[*elev].column, names[*elev], os.str());
      }
    }
    rows.push_back(r);
  }
  if (sep == 0)
    throw ScenarioError(path, std::max(lineNo, 1), 1, "",
                        "empty CSV: expected a header such as 'distance_km,grade_percent,speed_kmh'");
  if (rows.size() < 2)
    throw ScenarioError(path, lineNo, 1, "", "a route needs at least 2 points (its start and its end), got " +
                                                 std::to_string(rows.size()));
  std::vector<RouteSegment> segs;
  for (size_t i = 0; i + 1 < rows.size(); ++i)
    segs.push_back(RouteSegment{rows[i + 1].distance_m - rows[i].distance_m, rows[i].grade, rows[i].speed_m_per_s,
                                rows[i].headwind_m_per_s});
  return segs;
}

}  // namespace packsim
