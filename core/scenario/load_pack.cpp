#include <bms/bms_limits.hpp>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/scenario/scenario_sections.hpp"

namespace packsim {

// A curve is a number (constant), {poly: [...], axis}, or {x: [...], y: [...], axis}.
Curve readCurve(YamlMap& parent, const std::string& key, Range yRange) {
  const YAML::Node n = parent.node(key);
  if (n.IsScalar()) return Curve::constant(parent.number(key, yRange));
  YamlMap m = parent.map(key);
  const std::string axisName = m.choice("axis", "soc", {"soc", "discharged_Ah"});
  const CurveAxis axis = axisName == "soc" ? CurveAxis::Soc : CurveAxis::Discharged_Ah;
  Curve c;
  if (m.has("poly")) {
    if (m.has("x") || m.has("y")) throw m.error("give either poly or an x/y table, not both");
    c = Curve::polynomial(m.numbers("poly", Range{}), axis);
  } else if (m.has("x") || m.has("y")) {
    std::vector<double> xs = m.numbers("x", Range{}, 2);
    std::vector<double> ys = m.numbers("y", yRange, 2);
    if (xs.size() != ys.size())
      throw m.errorAt("y", "has " + std::to_string(ys.size()) + " values but x has " + std::to_string(xs.size()));
    for (size_t i = 1; i < xs.size(); ++i)
      if (!(xs[i] > xs[i - 1])) throw m.errorAt("x", "values must increase strictly");
    c = Curve::table(std::move(xs), std::move(ys), axis);
  } else {
    throw m.error("expected 'poly: [...]' (highest power first) or a table 'x: [...]', 'y: [...]'");
  }
  m.finish();
  return c;
}

CellParams readCell(YamlMap m) {
  CellParams c;
  c.capacity_Ah = m.number("capacity_Ah", Range::positive());
  c.ocv_V = readCurve(m, "ocv_V", Range::closed(0.0, 10.0));
  c.r0_ohm = readCurve(m, "r0_ohm", Range::positive());
  if (m.has("rc_pairs")) {
    for (YamlMap rc : m.mapList("rc_pairs")) {
      RcPair p;
      p.r_ohm = rc.number("r_ohm", Range::positive());
      if (rc.has("c_F") == rc.has("tau_s")) throw rc.error("give exactly one of c_F or tau_s");
      p.c_F = rc.has("c_F") ? rc.number("c_F", Range::positive()) : rc.number("tau_s", Range::positive()) / p.r_ohm;
      rc.finish();
      c.rc.push_back(p);
    }
  }
  c.coulombic_efficiency = m.number("coulombic_efficiency", 1.0, {0.0, 1.0, true, false});
  c.self_discharge_A = m.number("self_discharge_A", 0.0, Range::closed(0.0, 10.0));
  c.heat_capacity_J_per_K = m.number("heat_capacity_J_per_K", c.heat_capacity_J_per_K, Range::positive());
  c.g_ambient_W_per_K = m.number("g_ambient_W_per_K", c.g_ambient_W_per_K, Range::nonNegative());
  c.v_min_V = m.number("v_min_V", c.v_min_V, Range::closed(0.5, 5.0));
  c.v_max_V = m.number("v_max_V", c.v_max_V, Range::closed(0.5, 5.0));
  if (!(c.v_max_V > c.v_min_V)) throw m.errorAt("v_max_V", "must be above v_min_V");
  m.finish();
  return c;
}

PackConfig readPack(YamlMap m) {
  PackConfig p;
  p.series = static_cast<int>(m.integer("series", 1, bms::kMaxCells));
  p.parallel = static_cast<int>(m.integer("parallel", 1, 1, 1000));
  p.initial_soc = m.number("initial_soc", 1.0, Range::closed(0.0, 1.0));
  p.initial_temp_C = m.number("initial_temp_C", 25.0, Range::closed(-60.0, 150.0));
  p.cell = readCell(m.map("cell"));
  m.finish();
  return p;
}

}  // namespace packsim
