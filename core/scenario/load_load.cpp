#include <bms/bms_limits.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/value_ranges.hpp"
#include "core/scenario/column_units.hpp"
#include "core/scenario/csv_profile.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

// A load's current or power: the absolute bounds (value_ranges.hpp); the pack's own
// C-rate bound is checked once the pack is known (checkLoadCRate).
Range loadRange(const std::string& key) {
  return Range::symmetric(key == "power_W" ? limits::kMaxPower_W : limits::kMaxCurrent_A);
}

// A column whose name states a unit other than seconds, amperes or watts ("t_ms",
// "I [mA]") needs its scale said: read as it stands, a log in ms is a profile a thousand
// times too long. A scale given is the user's word (also time_scale: 1 for a name that
// only looks like a unit).
void checkNamedUnits(YamlMap& c, const CsvColumns& columns) {
  const struct {
    const char* columnKey;
    const char* scaleKey;
    std::string column;
    NamedUnit unit;
    const char* base;
  } named[] = {{"time_column", "time_scale", columns.time, timeUnitOfName(columns.time), "s"},
               {columns.power ? "power_column" : "current_column", "scale", columns.value,
                valueUnitOfName(columns.value, columns.power), columns.power ? "W" : "A"}};
  for (const auto& n : named) {
    if (n.unit.factor == 0.0 || n.unit.factor == 1.0 || c.has(n.scaleKey)) continue;
    std::ostringstream os;
    os << "the column '" << n.column << "' is named in " << n.unit.unit << " and packsim reads " << n.base
       << ": add " << n.scaleKey << ": " << n.unit.factor << " (or " << n.scaleKey << ": 1 if its values are in "
       << n.base << ")";
    throw c.errorAt(n.columnKey, os.str());
  }
}

// The most a load may ask of each parallel cell: 100C, twice the highest continuous
// rating any cell is sold with (hobby LiPo, ~50C; power-tool 18650s ~10C, LTO ~10-20C).
// A current logged in mA and read as A is 1000 times its size: even a 0.1C load then
// lands above this, so the mistake cannot pass as a hard but possible load.
constexpr double kMaxLoadCRate = 100.0;

// A load value (A, or W: at the pack's mid-charge open-circuit voltage) against the
// pack: "" when within kMaxLoadCRate, else why not.
struct LoadBound {
  double cells_Ah;  // parallel cells × capacity
  double pack_V;    // series × the cell's OCV at SOC 0.5
  int parallel;
  double cell_Ah;
  std::string check(double value, bool power) const {
    const double i_A = power ? value / pack_V : value;
    const double cRate = std::fabs(i_A) / cells_Ah;
    if (cRate <= kMaxLoadCRate) return "";
    std::ostringstream os;
    os << value << (power ? " W" : " A");
    if (power) os << " (" << i_A << " A at the pack's mid-charge voltage of " << pack_V << " V)";
    os << " is " << std::lround(cRate) << "C for the " << parallel << " parallel cell" << (parallel > 1 ? "s" : "")
       << " of " << cell_Ah << " Ah; allowed at most " << kMaxLoadCRate << "C (" << kMaxLoadCRate * cells_Ah
       << " A), twice the highest rating any cell is sold with. A value in m" << (power ? "W read as W" : "A read as A")
       << "? Divide by 1000 (for a CSV column: csv: {file, " << (power ? "power_column" : "current_column")
       << ", scale: 0.001})";
    return os.str();
  }
};

LoadBound loadBound(const PackConfig& pack) {
  LoadBound b;
  b.parallel = pack.parallel;
  b.cell_Ah = pack.cell.capacity_Ah;
  b.cells_Ah = pack.parallel * pack.cell.capacity_Ah;
  b.pack_V = std::max(1e-3, pack.series * pack.cell.ocv_V.eval(0.5, pack.cell.axis_capacity_Ah));
  return b;
}

}  // namespace

std::string loadCRateError(const PackConfig& pack, double value, bool power) {
  return loadBound(pack).check(value, power);
}

double shortCircuitCurrent_A(const PackConfig& pack) {
  // Over SOC 0..1 at 25 C: the highest OCV over the lowest R0 (a dead short on a cell).
  const CellParams& c = pack.cell;
  double ocv = 0.0, r0 = HUGE_VAL;
  for (int i = 0; i <= 100; ++i) {
    const double soc = i / 100.0;
    ocv = std::max(ocv, c.ocv_V.eval(soc, c.axis_capacity_Ah, kReferenceTemp_C));
    r0 = std::min(r0, c.r0_ohm.eval(soc, c.axis_capacity_Ah, kReferenceTemp_C));
  }
  return pack.parallel * ocv / r0;
}

// The load is a current (A) or a power (W) demand; each form names its quantity in
// its keys (current_A / power_W) so a profile cannot be misread.
LoadProfile readLoad(YamlMap m, const std::string& baseDir, const PackConfig& pack) {
  const LoadBound bound = loadBound(pack);
  // A value the pack's cells cannot carry: an error at its key (or list element).
  auto checkBound = [&](YamlMap& map, const std::string& key, double v, int index = -1) {
    const std::string why = bound.check(v, key == "power_W");
    if (why.empty()) return;
    if (index < 0) throw map.errorAt(key, why);
    throw map.errorAt(map.raw()[key][index], map.path() + "." + key + "[" + std::to_string(index) + "]", why);
  };
  const char* kinds[] = {"current_A", "power_W", "segments", "points", "csv"};
  int given = 0;
  for (const char* k : kinds) given += m.has(k) ? 1 : 0;
  if (given != 1) throw m.error("give exactly one of current_A / power_W (constant), segments, points or csv");

  using Q = LoadProfile::Quantity;
  auto pick = [](YamlMap& map) -> std::string {
    if (map.has("current_A") == map.has("power_W")) throw map.error("give exactly one of current_A or power_W");
    return map.has("current_A") ? "current_A" : "power_W";
  };
  LoadProfile p;
  if (m.has("current_A") || m.has("power_W")) {
    const std::string key = pick(m);
    p = LoadProfile::constant(m.number(key, loadRange(key)));
    checkBound(m, key, p.i_A.front());
    p.quantity = key == "current_A" ? Q::Current_A : Q::Power_W;
    m.finish();
    return p;
  }
  if (m.has("segments")) {
    double t = 0.0;
    std::string unit;
    for (YamlMap s : m.mapList("segments")) {
      const std::string key = pick(s);
      if (!unit.empty() && key != unit) throw s.errorAt(key, "all segments must give the same quantity (" + unit + ")");
      unit = key;
      p.t_s.push_back(t);
      p.i_A.push_back(s.number(key, loadRange(key)));
      checkBound(s, key, p.i_A.back());
      t += s.number("duration_s", Range::positive(limits::kMaxTime_s));
      s.finish();
    }
    p.quantity = unit == "current_A" ? Q::Current_A : Q::Power_W;
    p.t_s.push_back(t);
    p.i_A.push_back(0.0);  // end of lap; unused with step interpolation
    p.interp = LoadProfile::Interp::Step;
  } else {
    if (m.has("points")) {
      YamlMap pts = m.map("points");
      p.t_s = pts.numbers("time_s", Range::nonNegative(limits::kMaxTime_s), 2);
      const std::string key = pick(pts);
      p.quantity = key == "current_A" ? Q::Current_A : Q::Power_W;
      p.i_A = pts.numbers(key, loadRange(key), 2);
      for (size_t i = 0; i < p.i_A.size(); ++i) checkBound(pts, key, p.i_A[i], static_cast<int>(i));
      if (p.t_s.size() != p.i_A.size())
        throw pts.errorAt(key, "has " + std::to_string(p.i_A.size()) + " values but time_s has " +
                                   std::to_string(p.t_s.size()));
      if (p.t_s[0] != 0.0) throw pts.errorAt("time_s", "the first point must be at time 0");
      for (size_t i = 1; i < p.t_s.size(); ++i)
        if (!(p.t_s[i] > p.t_s[i - 1])) throw pts.errorAt("time_s", "values must increase strictly");
      pts.finish();
    } else {
      // csv: FILE (columns time_s and current_A or power_W), or
      // csv: {file, time_column, current_column | power_column, scale}.
      CsvColumns columns;
      fs::path csv;
      if (m.node("csv").IsMap()) {
        YamlMap c = m.map("csv");
        csv = c.string("file");
        columns.time = c.string("time_column", "time_s");
        if (c.has("current_column") && c.has("power_column"))
          throw c.errorAt("power_column", "give one of current_column or power_column");
        columns.power = c.has("power_column");
        columns.value = c.string(columns.power ? "power_column" : "current_column", "");
        columns.scale = c.number("scale", 1.0, Range::symmetric(1.0e6));  // mA, kW, MW and sign flips
        if (columns.scale == 0.0) throw c.errorAt("scale", "must not be 0");
        columns.time_scale = c.number("time_scale", 1.0, Range::positive(86400.0));  // ms, min, h
        checkNamedUnits(c, columns);
        c.finish();
        if (csv.is_relative()) csv = fs::path(baseDir) / csv;
        std::error_code ec;  // a name too long for the file system is "not found", not an exception
        if (!fs::exists(csv, ec)) throw c.errorAt("file", "file not found: " + csv.string());
      } else {
        csv = m.string("csv");
        if (csv.is_relative()) csv = fs::path(baseDir) / csv;
        std::error_code ec;
        if (!fs::exists(csv, ec)) throw m.errorAt("csv", "file not found: " + csv.string());
      }
      columns.check = [&bound](double v, bool power) { return bound.check(v, power); };
      const CsvProfile t = readProfileCsv(csv.string(), columns);
      p.t_s = t.time_s;
      p.i_A = t.value;
      p.quantity = t.power ? Q::Power_W : Q::Current_A;
    }
    p.interp = m.choice("interpolation", "step", {"step", "linear"}) == "step" ? LoadProfile::Interp::Step
                                                                              : LoadProfile::Interp::Linear;
  }
  p.laps = static_cast<int>(m.integer("laps", 1, 1, 100000));
  m.finish();
  return p;
}

RunConfig readRun(std::optional<YamlMap> m, uint64_t seed) {
  RunConfig r;
  r.seed = seed;
  if (!m) return r;
  r.duration_s = m->number("duration_s", 0.0, Range::positive(limits::kMaxTime_s));
  r.stop_after_trip_s = m->number("stop_after_trip_s", r.stop_after_trip_s, Range::nonNegative(limits::kMaxTime_s));
  r.solver = m->choice("solver", "cvode", {"cvode", "fast"}) == "fast" ? RunConfig::Solver::Fast
                                                                      : RunConfig::Solver::Cvode;
  // Settings of the other solver would silently do nothing: reject them.
  if (r.solver == RunConfig::Solver::Fast && m->has("rtol"))
    throw m->errorAt("rtol", "applies to solver: cvode only (this run uses solver: fast)");
  r.rtol = m->number("rtol", r.rtol, Range::closed(1e-12, 1e-2));
  if (r.solver == RunConfig::Solver::Fast && m->has("jacobian"))
    throw m->errorAt("jacobian", "applies to solver: cvode only (this run uses solver: fast)");
  r.jacobian = m->choice("jacobian", "sparse", {"sparse", "diagonal"}) == "diagonal" ? RunConfig::Jacobian::Diagonal
                                                                                   : RunConfig::Jacobian::Sparse;
  if (auto f = m->optionalMap("fast")) {
    if (r.solver != RunConfig::Solver::Fast)
      throw m->errorAt("fast", "settings for solver: fast, but this run uses solver: cvode (set run.solver: fast)");
    r.fast_max_substep_s = f->number("max_substep_s", 0.0, Range::positive(3600.0));
    r.fast_substep_fraction = f->number("substep_fraction", r.fast_substep_fraction, Range{0.0, 1.0, true, false});
    f->finish();
  }
  m->finish();
  return r;
}

}  // namespace packsim
