#include "core/scenario/route_csv.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/scenario/csv_table.hpp"
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
  TableReader csv(path);
  if (!csv.readHeader())
    throw ScenarioError(path, std::max(csv.line(), 1), 1, "",
                        "empty CSV: expected a header such as 'distance_km,grade_percent,speed_kmh'");
  const int headerLine = csv.line();
  const auto distKm = csv.column("distance_km"), distM = csv.column("distance_m");
  const auto grade = csv.column("grade_percent"), elev = csv.column("elevation_m");
  const auto speed = csv.column("speed_kmh"), headwind = csv.column("headwind_kmh");
  const auto wind = csv.column("wind_kmh"), windFrom = csv.column("wind_from_deg"), heading = csv.column("heading_deg");
  if (!distKm && !distM) throw csv.missing("'distance_km' or 'distance_m'", "distance_km");
  if (distKm && distM) throw ScenarioError(path, headerLine, 1, "distance_m", "give 'distance_km' or 'distance_m', not both");
  if (!grade && !elev) throw csv.missing("'grade_percent' or 'elevation_m'", "grade_percent");
  if (grade && elev) throw ScenarioError(path, headerLine, 1, "elevation_m", "give 'grade_percent' or 'elevation_m', not both");
  if (!speed) throw csv.missing("'speed_kmh'", "speed_kmh");
  const int windCols = (wind ? 1 : 0) + (windFrom ? 1 : 0) + (heading ? 1 : 0);
  if (windCols != 0 && windCols != 3)
    throw ScenarioError(path, headerLine, 1, wind ? (windFrom ? "heading_deg" : "wind_from_deg") : "wind_kmh",
                        "the wind by direction needs all of 'wind_kmh', 'wind_from_deg' and 'heading_deg'");
  if (windCols == 3 && headwind)
    throw ScenarioError(path, headerLine, 1, "headwind_kmh", "give 'headwind_kmh' or the wind by direction, not both");
  std::vector<Row> rows;
  while (csv.nextRow()) {
    Row r;
    r.line = csv.line();
    const size_t dcol = distKm ? *distKm : *distM;
    r.distance_m = distKm ? csv.value(dcol, 0.0, kMaxRoute_km, "km") * 1000.0 : csv.value(dcol, 0.0, kMaxRoute_km * 1000.0, "m");
    if (rows.empty() && r.distance_m != 0.0)
      throw csv.errorAt(dcol, "the first point must be at distance 0");
    if (!rows.empty() && !(r.distance_m > rows.back().distance_m)) {
      // Name the row it repeats or undercuts: a GPS log repeats its distance while the
      // vehicle stands (drop such rows), and a log joined from two files restarts at 0.
      std::ostringstream os;
      os.precision(10);
      os << "distance must increase strictly: " << csv.cell(dcol).text << " after "
         << (distKm ? rows.back().distance_m / 1000.0 : rows.back().distance_m) << " on line " << rows.back().line
         << (r.distance_m == rows.back().distance_m ? " (a repeated point: drop one of the two rows)" : "");
      throw csv.errorAt(dcol, os.str());
    }
    if (grade) r.grade = csv.value(*grade, -kMaxGrade_percent, kMaxGrade_percent, "%") / 100.0;
    if (elev) r.elevation_m = csv.value(*elev, kMinElevation_m, kMaxElevation_m, "m");
    // The speed of the last row is not used (the route ends there), but must still be valid.
    r.speed_m_per_s = csv.value(*speed, 0.0, kMaxSpeed_kmh, "km/h") / 3.6;
    if (!(r.speed_m_per_s > 0.0))
      throw csv.errorAt(*speed, "'" + csv.cell(*speed).text + "' is out of range; allowed (0, 360] km/h");
    if (headwind) r.headwind_m_per_s = csv.value(*headwind, -kMaxWind_kmh, kMaxWind_kmh, "km/h") / 3.6;
    if (wind) {
      const double w = csv.value(*wind, 0.0, kMaxWind_kmh, "km/h") / 3.6;
      const double from = csv.value(*windFrom, 0.0, 360.0, "degrees");
      const double head = csv.value(*heading, 0.0, 360.0, "degrees");
      r.headwind_m_per_s = w * std::cos((from - head) * kPi / 180.0);
    }
    if (elev && !rows.empty()) {  // the grade of the segment that ends here
      // The distance is along the road (the vehicle drives it): the road rises Δh over Δd
      // of road, sin θ = Δh/Δd, and the grade (rise over run) is tan θ -- so the segment
      // of length Δd climbs exactly Δh (docs/vehicle.md, "A route from a CSV").
      Row& prev = rows.back();
      const double rise_m = r.elevation_m - prev.elevation_m, road_m = r.distance_m - prev.distance_m;
      const double sinTheta = rise_m / road_m;
      const double maxSin = std::sin(std::atan(kMaxGrade_percent / 100.0));  // 45°
      if (std::fabs(sinTheta) > maxSin) {
        std::ostringstream os;
        os << "the elevation from line " << prev.line << " changes by " << rise_m << " m over " << road_m
           << " m of road, ";
        if (std::fabs(sinTheta) < 1.0)
          os << "a grade of " << sinTheta / std::sqrt(1.0 - sinTheta * sinTheta) * 100.0 << " %";
        else
          os << "as much as the road's length or more";
        os << "; allowed [-100, 100] % (the distance is along the road)";
        throw csv.errorAt(*elev, os.str());
      }
      prev.grade = sinTheta / std::sqrt(1.0 - sinTheta * sinTheta);
    }
    rows.push_back(r);
  }
  if (rows.size() < 2)
    throw ScenarioError(path, csv.line(), 1, "", "a route needs at least 2 points (its start and its end), got " +
                                                 std::to_string(rows.size()));
  std::vector<RouteSegment> segs;
  for (size_t i = 0; i + 1 < rows.size(); ++i)
    segs.push_back(RouteSegment{rows[i + 1].distance_m - rows[i].distance_m, rows[i].grade, rows[i].speed_m_per_s,
                                rows[i].headwind_m_per_s});
  return segs;
}

}  // namespace packsim
