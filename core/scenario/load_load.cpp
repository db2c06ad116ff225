#include <bms/bms_limits.hpp>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/csv_profile.hpp"

namespace packsim {

namespace fs = std::filesystem;

LoadProfile readLoad(YamlMap m, const std::string& baseDir) {
  const char* kinds[] = {"current_A", "segments", "points", "csv"};
  int given = 0;
  for (const char* k : kinds) given += m.has(k) ? 1 : 0;
  if (given != 1) throw m.error("give exactly one of current_A (constant), segments, points or csv");

  LoadProfile p;
  if (m.has("current_A")) {
    p = LoadProfile::constant(m.number("current_A", Range{}));
    m.finish();
    return p;
  }
  if (m.has("segments")) {
    double t = 0.0;
    for (YamlMap s : m.mapList("segments")) {
      p.t_s.push_back(t);
      p.i_A.push_back(s.number("current_A", Range{}));
      t += s.number("duration_s", Range::positive());
      s.finish();
    }
    p.t_s.push_back(t);
    p.i_A.push_back(0.0);  // end of lap; unused with step interpolation
    p.interp = LoadProfile::Interp::Step;
  } else {
    if (m.has("points")) {
      YamlMap pts = m.map("points");
      p.t_s = pts.numbers("time_s", Range::nonNegative(), 2);
      p.i_A = pts.numbers("current_A", Range{}, 2);
      if (p.t_s.size() != p.i_A.size())
        throw pts.errorAt("current_A", "has " + std::to_string(p.i_A.size()) + " values but time_s has " +
                                           std::to_string(p.t_s.size()));
      if (p.t_s[0] != 0.0) throw pts.errorAt("time_s", "the first point must be at time 0");
      for (size_t i = 1; i < p.t_s.size(); ++i)
        if (!(p.t_s[i] > p.t_s[i - 1])) throw pts.errorAt("time_s", "values must increase strictly");
      pts.finish();
    } else {
      fs::path csv = m.string("csv");
      if (csv.is_relative()) csv = fs::path(baseDir) / csv;
      if (!fs::exists(csv)) throw m.errorAt("csv", "file not found: " + csv.string());
      const CsvProfile t = readProfileCsv(csv.string());
      p.t_s = t.time_s;
      p.i_A = t.current_A;
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
  r.duration_s = m->number("duration_s", 0.0, Range::positive());
  r.stop_after_trip_s = m->number("stop_after_trip_s", r.stop_after_trip_s, Range::nonNegative());
  r.rtol = m->number("rtol", r.rtol, Range::closed(1e-12, 1e-2));
  m->finish();
  return r;
}

}  // namespace packsim
