// `load: {vehicle, route, driver, sun}` (docs/scenario.md, "Vehicle and route").
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>

#include "core/scenario/irradiance_csv.hpp"
#include "core/scenario/route_csv.hpp"
#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/value_ranges.hpp"

namespace packsim {

namespace {

std::string num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// Bounds of the vehicle keys, each with its reason.
// 100 t: a loaded heavy truck is 40 t; an eco-marathon car with its driver ~100 kg.
constexpr double kMaxMass_kg = 1.0e5;
// C_rr: 0.001 (a train on steel) .. 0.3 (sand); 1 leaves room for a test rig.
constexpr double kMaxRolling = 1.0;
// C_d·A: 0.03 m² (a shell-eco car) .. ~10 m² (a truck); 100 m² leaves room.
constexpr double kMaxDragArea_m2 = 100.0;
// Air: 0.5 kg/m³ at 6 km altitude .. 1.5 kg/m³ on a cold day at sea level; 5 leaves room.
constexpr double kMaxAirDensity_kg_per_m3 = 5.0;
// 100 m/s = 360 km/h.
constexpr double kMaxSpeed_kmh = 360.0;
// Grades: ±100 % (45°); the steepest public roads are ~35 %.
constexpr double kMaxGrade_percent = 100.0;
// Acceleration or braking up to 3 g.
constexpr double kMaxAccel_m_per_s2 = 30.0;
// A segment up to 1,000 km; a route of up to 100,000 laps.
constexpr double kMaxLength_m = 1.0e6;
// Wind along the road: the strongest gusts measured are ~400 km/h.
constexpr double kMaxWind_kmh = 400.0;
// A wheel up to 5 m across the radius (a mining truck's is ~2 m); wheel torque up to
// 1e5 N·m (a 40 t truck on a 35 % grade needs ~1.3e5 N at ~0.5 m: 6.5e4 N·m).
constexpr double kMaxWheelRadius_m = 5.0;
constexpr double kMaxWheelTorque_Nm = 1.0e5;
// A flat array up to 100 m² (a solar car carries ~4-6 m²).
constexpr double kMaxArrayArea_m2 = 100.0;

// An efficiency map (docs/vehicle.md, "Drivetrain efficiency map"): a wheel radius, the
// speed and torque axes from 0 strictly increasing, and one row of efficiencies per speed.
DrivetrainMap readEfficiencyMap(YamlMap m) {
  DrivetrainMap d;
  d.wheel_radius_m = m.number("wheel_radius_m", Range::positive(kMaxWheelRadius_m));
  auto axis = [&](const char* key, double hi, double scale) {
    std::vector<double> a = m.numbers(key, Range::nonNegative(hi), 2);
    if (a.front() != 0.0) throw m.errorAt(key, "must start at 0 (the map covers the vehicle from a standstill, at no load)");
    for (size_t i = 1; i < a.size(); ++i)
      if (!(a[i] > a[i - 1]))
        throw m.errorAt(key, "must increase strictly: entry " + std::to_string(i + 1) + " (" + num(a[i]) +
                                 ") after " + num(a[i - 1]));
    for (double& x : a) x *= scale;
    return a;
  };
  d.speed_m_per_s = axis("speed_kmh", kMaxSpeed_kmh, 1.0 / 3.6);
  d.torque_Nm = axis("torque_Nm", kMaxWheelTorque_Nm, 1.0);
  const YAML::Node rows = m.node("efficiency");
  const size_t nv = d.speed_m_per_s.size(), nt = d.torque_Nm.size();
  if (!rows.IsSequence() || rows.size() != nv)
    throw m.errorAt("efficiency", "must be a list of " + std::to_string(nv) + " rows, one per speed_kmh entry, each of " +
                                      std::to_string(nt) + " efficiencies (one per torque_Nm entry)");
  for (size_t i = 0; i < nv; ++i) {
    const YAML::Node row = rows[i];
    const std::string field = m.path() + ".efficiency[" + std::to_string(i) + "]";
    if (!row.IsSequence() || row.size() != nt)
      throw m.errorAt(row, field, "must be a list of " + std::to_string(nt) + " efficiencies (one per torque_Nm entry)");
    for (size_t j = 0; j < nt; ++j) {
      const std::string cell = field + "[" + std::to_string(j) + "]";
      double e = 0.0;
      if (quotedScalar(row[j])) throw m.errorAt(row[j], cell, quotedValueMessage(row[j], "expected a number"));
      try {
        e = row[j].as<double>();
      } catch (const YAML::Exception&) {
        throw m.errorAt(row[j], cell, "'" + row[j].Scalar() + "' is not a number; allowed (0, 1]");
      }
      if (!(e > 0.0 && e <= 1.0)) throw m.errorAt(row[j], cell, num(e) + " is out of range; allowed (0, 1]");
      d.efficiency.push_back(e);
    }
  }
  m.finish();
  return d;
}

VehicleParams readParams(YamlMap m, const PackConfig& pack) {
  VehicleParams p;
  p.mass_kg = m.number("mass_kg", Range::positive(kMaxMass_kg));
  p.rolling_coefficient = m.number("rolling_coefficient", Range::nonNegative(kMaxRolling));
  p.drag_area_m2 = m.number("drag_area_m2", Range::nonNegative(kMaxDragArea_m2));
  p.air_density_kg_per_m3 = m.number("air_density_kg_per_m3", 1.2, Range::nonNegative(kMaxAirDensity_kg_per_m3));
  if (m.has("drivetrain_efficiency") && m.node("drivetrain_efficiency").IsMap())
    p.efficiency_map = readEfficiencyMap(m.map("drivetrain_efficiency"));
  else
    p.drivetrain_efficiency = m.number("drivetrain_efficiency", Range::positive(1.0));
  p.max_drive_power_W = m.number("max_drive_power_W", Range::positive(limits::kMaxPower_W));
  if (const std::string why = loadCRateError(pack, p.max_drive_power_W, true); !why.empty())
    throw m.errorAt("max_drive_power_W", why);
  p.max_regen_power_W = m.number("max_regen_power_W", 0.0, Range::nonNegative(limits::kMaxPower_W));
  if (const std::string why = loadCRateError(pack, p.max_regen_power_W, true); !why.empty())
    throw m.errorAt("max_regen_power_W", why);
  p.aux_power_W = m.number("aux_power_W", 0.0, Range::nonNegative(limits::kMaxPower_W));
  if (p.aux_power_W >= p.max_drive_power_W)
    throw m.errorAt("aux_power_W", "must be below max_drive_power_W (" + num(p.max_drive_power_W) + " W)");
  p.max_current_A = m.number("max_current_A", 0.0, Range::nonNegative(limits::kMaxCurrent_A));
  if (m.has("cutoff_start_V") != m.has("cutoff_end_V"))
    throw m.errorAt(m.has("cutoff_start_V") ? "cutoff_start_V" : "cutoff_end_V",
                    "the low-voltage fold-back needs both cutoff_start_V and cutoff_end_V");
  if (m.has("cutoff_start_V")) {
    if (p.max_current_A <= 0.0)
      throw m.errorAt("cutoff_start_V", "the fold-back scales max_current_A: give max_current_A too");
    p.cutoff_start_V = m.number("cutoff_start_V", Range::positive(1.0e4));
    p.cutoff_end_V = m.number("cutoff_end_V", Range::nonNegative(1.0e4));
    if (!(p.cutoff_end_V < p.cutoff_start_V))
      throw m.errorAt("cutoff_end_V", "must be below cutoff_start_V (" + num(p.cutoff_start_V) + " V)");
  }
  m.finish();
  return p;
}

// route.stages and route.stops (docs/vehicle.md, "Stages and stops"): stops at the stage
// ends until the next stage's start time of day, and control stops of a set duration.
void readStops(YamlMap& m, Route& r, const SolarArray* sun) {
  const double total_m = r.total_m();
  std::vector<double> stageEnds_m;
  if (m.has("stages")) {
    std::vector<YamlMap> stages = m.mapList("stages");
    if (!sun)
      throw m.errorAt("stages", "a stage's start time of day needs the clock: give load.sun (its start_solar_hour is "
                                "the time of day at t = 0)");
    const double clock0_h = sun->start_solar_hour;
    int day = 0;
    double prevEnd_m = 0.0, prevStart_s = -1.0;
    for (size_t i = 0; i < stages.size(); ++i) {
      YamlMap& g = stages[i];
      const double end_m = g.number("end_km", Range::positive(total_m / 1000.0)) * 1000.0;
      const double hour = g.number("start_hour", Range{0.0, 24.0, false, true});
      day = static_cast<int>(g.integer("day", day + 1, 1, 366));
      g.finish();
      const bool last = i + 1 == stages.size();
      if (!(end_m > prevEnd_m))
        throw g.errorAt("end_km", "must be beyond the previous stage's end (" + num(prevEnd_m / 1000.0) + " km)");
      if (!last && !(end_m < total_m))
        throw g.errorAt("end_km", "must be before the route's end (" + num(total_m / 1000.0) + " km): only the last stage ends there");
      if (last && std::fabs(end_m - total_m) > 1e-6 * total_m)
        throw g.errorAt("end_km", "the last stage must end at the route's end, " + num(total_m / 1000.0) +
                                      " km (segments x laps)");
      const double start_s = ((day - 1) * 24.0 + hour - clock0_h) * 3600.0;
      if (start_s < 0.0)
        throw g.errorAt("start_hour", "stage " + std::to_string(i + 1) + " would start before t = 0 (load.sun.start_solar_hour " +
                                          num(clock0_h) + " on day 1)");
      if (!(start_s > prevStart_s))
        throw g.errorAt(g.has("day") ? "day" : "start_hour", "must start after stage " + std::to_string(i) +
                                                                 " (give a later day or hour)");
      // The stop before this stage: the start line (stage 1) or the previous stage's end.
      r.stops.push_back(RouteStop{prevEnd_m, 0.0, start_s, static_cast<int>(i)});
      if (!last) stageEnds_m.push_back(end_m);
      prevEnd_m = end_m;
      prevStart_s = start_s;
    }
    r.stages = static_cast<int>(stages.size());
  }
  if (m.has("stops")) {
    double prev_m = 0.0;
    for (YamlMap c : m.mapList("stops")) {
      const double at_m = c.number("at_km", Range{0.0, total_m / 1000.0, true, true}) * 1000.0;
      const double dur_s = c.number("duration_s", Range::positive(limits::kMaxTime_s));
      c.finish();
      if (!(at_m > prev_m)) throw c.errorAt("at_km", "must be beyond the previous stop (" + num(prev_m / 1000.0) + " km)");
      for (double e : stageEnds_m)
        if (e == at_m) throw c.errorAt("at_km", "is a stage's end (a stop already): give a place inside a stage");
      r.stops.push_back(RouteStop{at_m, dur_s, 0.0, -1});
      prev_m = at_m;
    }
  }
  // Places are distinct (stage ends increase, a control stop is never one), so a plain
  // sort is stable here; std::stable_sort's temporary buffer trips ASan's
  // alloc-dealloc-mismatch with GCC 12's libstdc++.
  std::sort(r.stops.begin(), r.stops.end(), [](const RouteStop& a, const RouteStop& b) { return a.at_m < b.at_m; });
}

// Laps of a circuit: the lap must end at the height it starts at. A lap that climbs a net h
// (a GPS log's last altitude a few metres off its first) lifts the vehicle h again every
// lap and never brings it down: m·g·h a lap of work no circuit asks for, silently in
// every lap's Wh (3 m on a 150 kg eco car: 1.5 Wh of a 9.5 Wh lap).
void checkLapCloses(YamlMap& m, const Route& r, bool table) {
  // Σ length · sin θ (the length is along the road, the grade tan θ): a table's last
  // elevation_m less its first
  double rise_m = 0.0;
  for (const RouteSegment& g : r.segments) rise_m += g.length_m * g.grade / std::sqrt(1.0 + g.grade * g.grade);
  constexpr double kClosed_m = 1e-3;  // 1 mm: rounding of the table's numbers, not a hill
  if (std::fabs(rise_m) <= kClosed_m) return;
  std::ostringstream os;
  os.precision(4);
  const char* way = rise_m > 0.0 ? "climb" : "descend";
  os << r.laps << " laps of a route that does not close: each lap would " << way << " a net " << std::fabs(rise_m)
     << " m (the sum of length x sin(atan(grade)) over the lap" << (table ? "; by elevation_m, the last row's less the first's" : "")
     << ") and " << way << " it again on the next, " << std::fabs(rise_m) * r.laps
     << " m in all, and every lap's energy would hold that m*g*h. A circuit ends where it starts: "
     << (table ? "end the table at its first row's height (a GPS altitude drifts by metres)"
               : "make the segments' grades add up to no net climb")
     << ", or drive the route once (laps: 1)";
  throw m.errorAt("laps", os.str());
}

// A file named relative to the scenario's folder, which must exist.
std::string scenarioFile(YamlMap& m, const char* key, const std::string& baseDir) {
  const std::string rel = m.string(key);
  const std::filesystem::path path =
      std::filesystem::path(rel).is_relative() ? std::filesystem::path(baseDir) / rel : std::filesystem::path(rel);
  if (!std::filesystem::exists(path)) throw m.errorAt(key, "file not found: " + path.string());
  return path.string();
}

Route readRoute(YamlMap m, const SolarArray* sun, const std::string& baseDir) {
  Route r;
  if (m.has("csv")) {  // a route table (core/scenario/route_csv.hpp)
    if (m.has("segments")) {  // an empty list clears a base scenario's segments
      const YAML::Node segs = m.node("segments");
      if (!segs.IsSequence() || segs.size() != 0)
        throw m.errorAt("segments", "give segments or csv, not both (a scenario extending one with segments: set "
                                    "segments: [])");
    }
    r.segments = readRouteCsv(scenarioFile(m, "csv", baseDir));
  } else {
    for (YamlMap s : m.mapList("segments")) {
      RouteSegment g;
      g.length_m = s.number("length_m", Range::positive(kMaxLength_m));
      g.grade = s.number("grade_percent", 0.0, Range::symmetric(kMaxGrade_percent)) / 100.0;
      g.speed_m_per_s = s.number("speed_kmh", Range::positive(kMaxSpeed_kmh)) / 3.6;
      g.headwind_m_per_s = s.number("headwind_kmh", 0.0, Range::symmetric(kMaxWind_kmh)) / 3.6;
      s.finish();
      r.segments.push_back(g);
    }
  }
  r.laps = static_cast<int>(m.integer("laps", 1, 1, 100000));
  if (r.laps > 1) checkLapCloses(m, r, m.has("csv"));
  r.time_limit_s = m.number("time_limit_s", 0.0, Range::nonNegative(limits::kMaxTime_s));
  readStops(m, r, sun);
  m.finish();
  return r;
}

DriverParams readDriver(std::optional<YamlMap> m) {
  DriverParams d;
  if (!m) return d;
  d.accel_m_per_s2 = m->number("accel_m_per_s2", d.accel_m_per_s2, Range::positive(kMaxAccel_m_per_s2));
  d.brake_m_per_s2 = m->number("brake_m_per_s2", d.brake_m_per_s2, Range::positive(kMaxAccel_m_per_s2));
  d.response_s = m->number("response_s", d.response_s, Range::positive(3600.0));
  d.power_cap_W = m->number("power_cap_W", 0.0, Range::nonNegative(limits::kMaxPower_W));
  d.max_speed_m_per_s = m->number("max_speed_kmh", 0.0, Range::nonNegative(kMaxSpeed_kmh)) / 3.6;
  // Up to 1 MWh a lap (a long lap of a truck); 0: no such strategy.
  d.lap_energy_J = m->number("lap_energy_Wh", 0.0, Range::nonNegative(1.0e6)) * 3600.0;
  m->finish();
  return d;
}

SolarArray readSun(YamlMap m, const std::string& baseDir) {
  SolarArray a;
  a.area_m2 = m.number("array_area_m2", Range::positive(kMaxArrayArea_m2));
  a.efficiency = m.number("efficiency", Range::positive(1.0));
  a.mppt_efficiency = m.number("mppt_efficiency", 1.0, Range::positive(1.0));
  if (m.has("irradiance_csv")) {  // a measured or forecast irradiance table instead of the clear sky
    for (const char* k : {"latitude_deg", "day_of_year"})
      if (m.has(k))
        throw m.errorAt(k, "not used with irradiance_csv (the table gives the irradiance): give one or the other");
    a.table = readIrradianceCsv(scenarioFile(m, "irradiance_csv", baseDir));
  } else {
    a.where.latitude_deg = m.number("latitude_deg", Range::closed(-90.0, 90.0));
    a.where.day_of_year = static_cast<int>(m.integer("day_of_year", 1, 366));
  }
  a.start_solar_hour = m.number("start_solar_hour", Range{0.0, 24.0, false, true});
  m.finish();
  return a;
}

}  // namespace

VehicleConfig readVehicle(YamlMap& load, const PackConfig& pack, const std::string& baseDir) {
  VehicleConfig c;
  c.present = true;
  c.params = readParams(load.map("vehicle"), pack);
  YamlMap route = load.map("route");
  c.driver = readDriver(load.optionalMap("driver"));
  if (auto sun = load.optionalMap("sun")) c.array = readSun(*sun, baseDir);
  c.route = readRoute(route, c.array.area_m2 > 0.0 ? &c.array : nullptr, baseDir);
  c.standstill_end_s = load.number("standstill_end_s", c.standstill_end_s, Range::positive(limits::kMaxTime_s));
  return c;
}

}  // namespace packsim
