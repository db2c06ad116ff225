#include <bms/bms_limits.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <utility>

#include "core/scenario/curve_domain.hpp"
#include "core/scenario/load_scenario.hpp"
#include "core/scenario/provenance.hpp"
#include "core/scenario/scenario_warnings.hpp"
#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/value_ranges.hpp"
#include "core/scenario/yaml_layers.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {
// A curve's x values are SOC or discharged Ah (at most a cell's capacity); a
// polynomial's coefficients stay within +-1e9 (the curve checks then bound its values).
const Range kAxis = Range::symmetric(limits::kMaxCapacity_Ah);
const Range kCoefficients = Range::symmetric(1.0e9);
const Range kResistance = Range::positive(limits::kMaxCellResistance_ohm);
}  // namespace

// A curve is a number (constant), {poly: [...], axis}, {x: [...], y: [...], axis}, or a
// 2-D table {x: [...], temp_C: [...], y: [[row at temp_C[0]], …], axis}; a 1-D form
// may carry an Arrhenius factor {arrhenius_K, ref_temp_C}.
Curve readCurve(YamlMap& parent, const std::string& key, Range yRange) {
  const YAML::Node n = parent.node(key);
  if (n.IsScalar()) return Curve::constant(parent.number(key, yRange));
  YamlMap m = parent.map(key);
  const std::string axisName = m.choice("axis", "soc", {"soc", "discharged_Ah"});
  const CurveAxis axis = axisName == "soc" ? CurveAxis::Soc : CurveAxis::Discharged_Ah;
  Curve c;
  if (m.has("poly")) {
    if (m.has("temp_C"))
      throw m.errorAt("temp_C", "a polynomial has no temp_C rows (those are a 2-D table's): give arrhenius_K and "
                                "ref_temp_C for its temperature law (arrhenius_K: 0 for none), or a 2-D table");
    if (m.has("x") || m.has("y")) throw m.error("give either poly or an x/y table, not both");
    c = Curve::polynomial(m.numbers("poly", kCoefficients), axis);
  } else if (m.has("x") || m.has("y")) {
    std::vector<double> xs = m.numbers("x", kAxis, 2);
    for (size_t i = 1; i < xs.size(); ++i)
      if (!(xs[i] > xs[i - 1])) throw m.errorAt("x", "values must increase strictly");
    if (m.has("temp_C")) {
      std::vector<double> temps = m.numbers("temp_C", Range::closed(-60.0, 150.0), 1);
      for (size_t i = 1; i < temps.size(); ++i)
        if (!(temps[i] > temps[i - 1])) throw m.errorAt("temp_C", "values must increase strictly");
      const YAML::Node rowsNode = m.node("y");
      if (!rowsNode.IsSequence() || rowsNode.size() != temps.size())
        throw m.errorAt("y", "a 2-D table needs one row of y per temp_C value (" + std::to_string(temps.size()) +
                                 " rows); for a curve over x alone state its temperature law instead of the rows "
                                 "(arrhenius_K and ref_temp_C; arrhenius_K: 0 for none)");
      const std::string yField = m.path().empty() ? "y" : m.path() + ".y";
      std::vector<std::vector<double>> rows;
      for (size_t j = 0; j < rowsNode.size(); ++j) {
        const YAML::Node row = rowsNode[j];
        char rowName[64];
        std::snprintf(rowName, sizeof rowName, "row %zu (temp_C %g)", j + 1, temps[j]);
        if (!row.IsSequence() || row.size() != xs.size())
          throw m.errorAt(row, yField, std::string(rowName) + " needs " + std::to_string(xs.size()) + " values, one per x");
        std::vector<double> r;
        for (const YAML::Node& v : row) {
          double d = 0.0;
          if (quotedScalar(v))
            throw m.errorAt(v, yField, std::string(rowName) + ": " + quotedValueMessage(v, "expected a number"));
          if (!v.IsScalar() || !YAML::convert<double>::decode(v, d) || !std::isfinite(d))
            throw m.errorAt(v, yField, std::string(rowName) + ": expected a finite number");
          if (!yRange.contains(d))
            throw m.errorAt(v, yField, std::string(rowName) + ": value " + v.Scalar() + " is out of range; allowed " + yRange.describe());
          r.push_back(d);
        }
        rows.push_back(std::move(r));
      }
      c = Curve::table2d(std::move(xs), std::move(temps), rows, axis);
    } else {
      std::vector<double> ys = m.numbers("y", yRange, 2);
      if (xs.size() != ys.size())
        throw m.errorAt("y", "has " + std::to_string(ys.size()) + " values but x has " + std::to_string(xs.size()));
      c = Curve::table(std::move(xs), std::move(ys), axis);
    }
  } else {
    throw m.error("expected 'poly: [...]' (highest power first), a table 'x: [...]', 'y: [...]', or a 2-D table "
                  "'x: [...]', 'temp_C: [...]', 'y: [[...], ...]'");
  }
  if (m.has("arrhenius_K") || m.has("ref_temp_C")) {
    if (c.kind == Curve::Kind::Table2D)
      throw m.error("a 2-D table over temp_C carries its temperature dependence; drop arrhenius_K / ref_temp_C");
    const double k = m.number("arrhenius_K", Range::closed(-30000.0, 30000.0));
    const double ref = m.number("ref_temp_C", Range::closed(-60.0, 150.0));
    c = c.withArrhenius(k, ref);
  }
  m.finish();
  return c;
}

namespace {

// Reads a curve and checks it over SOC 0..1 (and its temperatures): see curve_domain.hpp.
Curve readCheckedCurve(YamlMap& m, const std::string& key, Range yRange, CurveRule rule, double axis_capacity_Ah) {
  Curve c = readCurve(m, key, yRange);
  const double maxAbs = std::max(std::fabs(yRange.lo), std::fabs(yRange.hi));
  if (auto err = curveDomainError(c, rule, axis_capacity_Ah, maxAbs)) throw m.errorAt(key, *err);
  return c;
}

}  // namespace

// axis_capacity_Ah: the nominal capacity the curves over discharged Ah refer to (the
// preset's); 0: this cell's own capacity_Ah.
CellParams readCell(YamlMap m, double axis_capacity_Ah) {
  CellParams c;
  c.capacity_Ah = m.number("capacity_Ah", Range::positive(limits::kMaxCapacity_Ah));
  c.axis_capacity_Ah = axis_capacity_Ah > 0.0 ? axis_capacity_Ah : c.capacity_Ah;
  const double q = c.axis_capacity_Ah;
  c.ocv_V = readCheckedCurve(m, "ocv_V", Range::closed(0.0, 10.0), CurveRule::Ocv, q);
  c.r0_ohm = readCheckedCurve(m, "r0_ohm", kResistance, CurveRule::Positive, q);
  if (m.has("r0_charge_ohm")) {
    c.has_r0_charge = true;
    c.r0_charge_ohm = readCheckedCurve(m, "r0_charge_ohm", kResistance, CurveRule::Positive, q);
  }
  if (m.has("docv_dT_V_per_K")) {
    c.has_entropic = true;
    c.docv_dT_V_per_K = readCheckedCurve(m, "docv_dT_V_per_K", Range::closed(-0.01, 0.01), CurveRule::Finite, q);
  }
  if (auto h = m.optionalMap("hysteresis")) {
    c.has_hysteresis = true;
    c.hysteresis_max_V = readCheckedCurve(*h, "max_V", Range::closed(0.0, 1.0), CurveRule::NonNegative, q);
    c.hysteresis_rate_per_Ah = h->number("rate_per_Ah", Range{0.0, 1e5, true, false});
    c.hysteresis_instant_V = h->number("instantaneous_V", 0.0, Range::closed(0.0, 1.0));
    h->finish();
  }
  if (m.has("rc_pairs")) {
    for (YamlMap rc : m.mapList("rc_pairs")) {
      RcPair p;
      if (rc.has("c_F") == rc.has("tau_s")) throw rc.error("give exactly one of c_F or tau_s");
      p.by_tau = rc.has("tau_s");
      const std::string cKey = p.by_tau ? "tau_s" : "c_F";
      p.r_curve = readCheckedCurve(rc, "r_ohm", kResistance, CurveRule::Positive, q);
      Curve cc = readCheckedCurve(rc, cKey, p.by_tau ? Range::positive(1.0e6) : Range::positive(1.0e8), CurveRule::Positive, q);
      p.variable = !p.r_curve.isConstant() || !cc.isConstant();
      if (p.variable) {
        (p.by_tau ? p.tau_curve : p.c_curve) = cc;
      } else {
        p.r_ohm = p.r_curve.coeffs()[0];
        p.c_F = p.by_tau ? cc.coeffs()[0] / p.r_ohm : cc.coeffs()[0];
      }
      rc.finish();
      c.rc.push_back(p);
    }
  }
  c.coulombic_efficiency = m.number("coulombic_efficiency", 1.0, {0.0, 1.0, true, false});
  c.self_discharge_A = m.number("self_discharge_A", 0.0, Range::closed(0.0, 10.0));
  c.heat_capacity_J_per_K = m.number("heat_capacity_J_per_K", c.heat_capacity_J_per_K, Range::positive(limits::kMaxHeatCapacity_J_per_K));
  c.g_ambient_W_per_K = m.number("g_ambient_W_per_K", c.g_ambient_W_per_K, Range::nonNegative(limits::kMaxConductance_W_per_K));
  c.v_min_V = m.number("v_min_V", c.v_min_V, Range::closed(0.5, 5.0));
  c.v_max_V = m.number("v_max_V", c.v_max_V, Range::closed(0.5, 5.0));
  if (!(c.v_max_V > c.v_min_V)) throw m.errorAt("v_max_V", "must be above v_min_V");
  c.max_charge_C = m.number("max_charge_C", 0.0, Range::closed(0.0, 100.0));
  c.max_discharge_C = m.number("max_discharge_C", 0.0, Range::closed(0.0, 1000.0));
  m.finish();
  return c;
}

namespace {

// The scenario's own cells/ first; the bundled folder is neither needed nor looked for
// when the preset is there (an FMU carries its preset so, docs/fmu.md).
std::vector<std::string> presetDirs(const std::string& baseDir, const std::string& name) {
  std::error_code ec;
  if (fs::exists(baseDir + "/cells/" + name + ".yaml", ec)) return {baseDir + "/cells"};
  return cellPresetDirs(baseDir);
}

// A single value given for a preset's curve is the value at the reference temperature:
// the preset's temperature law still applies to it. Arrhenius: the same factor (same
// arrhenius_K and ref_temp_C). A 2-D table over temp_C: the preset's table scaled so that
// it reads v at 25 C at every x (each row keeps its ratio to the 25 C value). (A curve
// given as a mapping was merged onto the preset's, law included: yaml_layers.hpp.)
Curve withPresetTemperatureLaw(const Curve& preset, const Curve& given) {
  if (preset.kind != Curve::Kind::Table2D) return given.withArrhenius(preset.arrhenius_K, preset.ref_temp_C);
  const double v = given.coeffs()[0];
  for (const double x : preset.xs())
    if (preset.at(x, kReferenceTemp_C) == 0.0)
      throw std::invalid_argument(
          "the preset's curve is a table over temp_C that is 0 at 25 C, so a single value cannot keep its temperature "
          "ratios: give a 2-D table (x, temp_C, y rows), or state the law (arrhenius_K and ref_temp_C; arrhenius_K: 0 "
          "for none)");
  std::vector<std::vector<double>> rows;
  for (const double t : preset.temps_C()) {
    std::vector<double> row;
    for (const double x : preset.xs()) row.push_back(v * (preset.at(x, t) / preset.at(x, kReferenceTemp_C)));
    rows.push_back(std::move(row));
  }
  return Curve::table2d(preset.xs(), preset.temps_C(), rows, preset.axis);
}

// `cell: {preset: NAME, <field>: <override>…}`: the preset file (cells/NAME.yaml next
// to the scenario, or bundled) is validated on its own, then the scenario's fields
// replace the preset's one by one.
CellParams readCellWithPreset(YamlMap m, const std::string& baseDir) {
  if (!m.has("preset")) {
    // Neither a preset nor an inline cell's curves: a misspelt key (`prest:`, `fle:`) is
    // the likelier cause than a missing curve, so the keys given are named.
    if (!m.has("ocv_V") && !m.has("r0_ohm")) {
      std::string given;
      for (auto it = m.raw().begin(); it != m.raw().end(); ++it)
        given += (given.empty() ? "'" : ", '") + it->first.Scalar() + "'";
      throw m.error("a cell is a preset ('preset: NAME', with overrides) or inline (capacity_Ah, ocv_V, r0_ohm, "
                    "...); this one has neither 'preset' nor 'ocv_V' and 'r0_ohm'" +
                    (given.empty() ? std::string() : " (keys given: " + given + ")"));
    }
    return readCell(m);
  }
  const std::string name = m.string("preset");
  std::string path;
  std::vector<std::string> known;
  for (const std::string& dir : presetDirs(baseDir, name)) {
    std::error_code ec;  // a name too long for the file system is "unknown", not an exception
    if (!fs::is_directory(dir, ec)) continue;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().extension() == ".yaml") known.push_back(e.path().stem().string());
    if (path.empty() && fs::exists(dir + "/" + name + ".yaml", ec)) path = dir + "/" + name + ".yaml";
  }
  if (path.empty()) {
    std::sort(known.begin(), known.end());
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
    const std::string near = closestMatch(name, known);
    // A file name given as the preset (`packsim fit -o my_cell.yaml`): say how presets are found.
    const bool fileName = name.size() > 5 && name.compare(name.size() - 5, 5, ".yaml") == 0;
    throw m.errorAt("preset", "unknown cell preset '" + name + "'" +
                                  (fileName ? "; a preset is named without '.yaml' and found as cells/" +
                                                  name.substr(0, name.size() - 5) + ".yaml next to the scenario"
                                   : near.empty() ? ""
                                                  : "; did you mean '" + near + "'?") +
                                  " (available: " + list + ")");
  }
  const std::string presetText = readScenarioText(path, "cell preset");
  const YAML::Node preset = parseYaml(presetText, path);
  CellParams nominal;
  {
    Provenance::Scope pause(nullptr);  // the preset alone must be valid (its keys are recorded below)
    nominal = readCell(YamlMap(preset, path, ""));
  }
  // A second parse, not YAML::Clone (which loses the lines) nor the tree just read (whose
  // lookups of absent keys left entries that would shadow an inserted key).
  YAML::Node merged = parseYaml(presetText, path);
  const YAML::Node& cmerged = merged;  // const: a lookup must not add the key
  Provenance* prov = Provenance::active();
  // The fields the scenario gives, for `show`: a curve given over the preset's names its
  // parts (`ocv_V.y`), so what the preset's curve keeps (its x grid, its law) is shown
  // as the preset's.
  std::vector<std::string> given;
  for (auto it = m.raw().begin(); it != m.raw().end(); ++it) {
    const std::string key = it->first.Scalar();
    if (it->second.IsMap() && isCurveMapping(cmerged[key])) {
      for (auto part = it->second.begin(); part != it->second.end(); ++part)
        given.push_back(key + "." + part->first.Scalar());
    } else {
      given.push_back(key);
    }
  }
  if (prov) prov->addPresetScope(m.path(), name, path, given);
  for (auto it = m.raw().begin(); it != m.raw().end(); ++it) {
    const std::string key = it->first.Scalar();
    if (key == "preset") continue;
    // `field: null` removes the preset's field (its default applies; yaml_layers.hpp).
    if (removesKey(it->second)) {
      if (cmerged[key]) merged.remove(key);
      continue;
    }
    // A curve given as a mapping over the preset's curve changes the parts it gives and
    // keeps the rest (`ocv_V: {y: [...]}` keeps the preset's x grid, axis and temperature
    // law); one that states its form or law replaces those (yaml_layers.hpp).
    if (it->second.IsMap() && isCurveMapping(cmerged[key])) {
      YAML::Node curve = merged[key];
      dropReplacedAlternatives(curve, it->second, m.path() + "." + key);
      for (auto part = it->second.begin(); part != it->second.end(); ++part) {
        const std::string partKey = part->first.Scalar();
        if (removesKey(part->second)) curve.remove(partKey);
        else if (static_cast<const YAML::Node&>(curve)[partKey]) curve[partKey] = part->second;
        else curve.force_insert(part->first, part->second);
      }
      continue;
    }
    // The scenario's own value node (and key node, for a key the preset lacks), so an
    // error keeps its line and column.
    if (cmerged[key]) merged[key] = it->second;
    else merged.force_insert(it->first, it->second);
  }
  const std::pair<const char*, Curve CellParams::*> curves[] = {{"ocv_V", &CellParams::ocv_V},
                                                                {"r0_ohm", &CellParams::r0_ohm},
                                                                {"r0_charge_ohm", &CellParams::r0_charge_ohm},
                                                                {"docv_dT_V_per_K", &CellParams::docv_dT_V_per_K}};
  // A new curve over x alone (its form, no law) cannot carry a 2-D preset's temp_C rows.
  for (const auto& [key, member] : curves) {
    const YAML::Node stated = m.raw()[key];
    if ((nominal.*member).kind == Curve::Kind::Table2D && stated && stated.IsMap() &&
        (stated["poly"] || stated["x"]) && !stated["temp_C"] && !stated["arrhenius_K"] && !stated["ref_temp_C"])
      throw m.errorAt(key, "the preset's curve is a table over temp_C; a curve over x alone would drop its temperature "
                           "dependence: give a single value (the value at 25 C; the preset's temperature ratios are "
                           "kept), a 2-D table (x, temp_C, y rows), or state the law (arrhenius_K and ref_temp_C; "
                           "arrhenius_K: 0 for none) (preset " + name + ")");
  }
  // Curves over discharged Ah keep meaning the preset's discharged charge, even where
  // the scenario gives this cell another capacity.
  CellParams cell = readCell(YamlMap(merged, m.file(), m.path()), nominal.capacity_Ah);
  for (const auto& [key, member] : curves) {
    const YAML::Node stated = m.raw()[key];
    // A mapping was merged onto the preset's curve above: it keeps the preset's law
    // unless it states its own.
    if (!stated || stated.IsMap() || !(nominal.*member).dependsOnTemperature()) continue;
    try {
      cell.*member = withPresetTemperatureLaw(nominal.*member, cell.*member);
    } catch (const std::invalid_argument& e) {
      throw m.errorAt(key, std::string(e.what()) + " (preset " + name + ")");
    }
  }
  if (prov) presetDependenceWarnings(m.path(), nominal, cell, m.raw(), "preset " + name, *prov);
  return cell;
}

CellSpread readSpread(YamlMap m) {
  CellSpread s;
  s.capacity_rel_sd = m.number("capacity_rel_sd", 0.0, Range::closed(0.0, 0.3));
  s.r0_rel_sd = m.number("r0_rel_sd", 0.0, Range::closed(0.0, 0.3));
  s.initial_soc_sd = m.number("initial_soc_sd", 0.0, Range::closed(0.0, 0.3));
  s.self_discharge_A_sd = m.number("self_discharge_A_sd", 0.0, Range::closed(0.0, 1.0));
  s.per_group = m.choice("level", "cell", {"cell", "group"}) == "group";
  m.finish();
  return s;
}

CellOverride readCellOverride(YamlMap m, int cells) {
  CellOverride o;
  o.cell = static_cast<int>(m.integer("cell", 1, cells)) - 1;
  if (m.has("capacity_Ah")) o.capacity_Ah = m.number("capacity_Ah", Range::positive(limits::kMaxCapacity_Ah));
  if (m.has("r0_scale")) o.r0_scale = m.number("r0_scale", Range::closed(0.1, 10.0));
  if (m.has("initial_soc")) o.initial_soc = m.number("initial_soc", Range::closed(0.0, 1.0));
  if (m.has("self_discharge_A")) o.self_discharge_A = m.number("self_discharge_A", Range::closed(0.0, 10.0));
  m.finish();
  return o;
}

// `cell: ncr18650_3p1Ah` (a preset's name where the mapping belongs) is the likeliest
// first try: the error shows the mapping that names the preset.
YamlMap cellMap(YamlMap& m) {
  const YAML::Node n = m.raw()["cell"];
  if (n && n.IsScalar())
    throw m.errorAt("cell", "expected a mapping: a preset is given as 'cell: {preset: " + n.Scalar() +
                                "}' (with any field to override beside it), an inline cell as capacity_Ah, ocv_V, "
                                "r0_ohm, ...");
  return m.map("cell");
}

}  // namespace

PackConfig readPack(YamlMap m, const std::string& baseDir) {
  PackConfig p;
  p.series = static_cast<int>(m.integer("series", 1, bms::kMaxCells));
  p.parallel = static_cast<int>(m.integer("parallel", 1, 1, 1000));
  p.initial_soc = m.number("initial_soc", 1.0, Range::closed(0.0, 1.0));
  p.initial_temp_C = m.number("initial_temp_C", 25.0, Range::closed(-60.0, 150.0));
  p.interconnect_ohm = m.number("interconnect_ohm", 0.0, Range::closed(0.0, 10.0));
  p.cell = readCellWithPreset(cellMap(m), baseDir);
  if (auto sp = m.optionalMap("spread")) p.spread = readSpread(*sp);
  if (m.has("cells"))
    for (YamlMap c : m.mapList("cells")) p.cell_overrides.push_back(readCellOverride(c, p.series * p.parallel));
  m.finish();
  return p;
}

ThermalConfig readThermal(std::optional<YamlMap> m, int cells) {
  ThermalConfig t;
  if (!m) return t;
  t.cell_to_cell_W_per_K = m->number("cell_to_cell_W_per_K", 0.0, Range::nonNegative(limits::kMaxConductance_W_per_K));
  t.g_coolant_W_per_K = m->number("cell_to_coolant_W_per_K", 0.0, Range::nonNegative(limits::kMaxConductance_W_per_K));
  t.coolant_C = m->number("coolant_temp_C", 25.0, Range::closed(-60.0, 150.0));
  if (m->has("nodes")) {
    std::vector<YamlMap> linkSites;  // where each to_nodes entry was written (for errors)
    for (YamlMap n : m->mapList("nodes")) {
      ThermalNodeConfig c;
      c.name = n.string("name");
      for (const auto& other : t.nodes)
        if (other.name == c.name) throw n.errorAt("name", "duplicate thermal node '" + c.name + "'");
      c.heat_capacity_J_per_K = n.number("heat_capacity_J_per_K", Range::positive(limits::kMaxHeatCapacity_J_per_K));
      c.g_ambient_W_per_K = n.number("g_ambient_W_per_K", 0.0, Range::nonNegative(limits::kMaxConductance_W_per_K));
      c.g_each_cell_W_per_K = n.number("to_each_cell_W_per_K", 0.0, Range::nonNegative(limits::kMaxConductance_W_per_K));
      c.heat_W = n.number("heat_W", 0.0, Range::closed(0.0, 1e6));
      if (n.has("to_cells")) {
        for (YamlMap l : n.mapList("to_cells")) {
          const int cell = static_cast<int>(l.integer("cell", 1, cells)) - 1;
          c.cell_links.emplace_back(cell, l.number("g_W_per_K", Range::positive(limits::kMaxConductance_W_per_K)));
          l.finish();
        }
      }
      if (n.has("to_nodes")) {
        for (YamlMap l : n.mapList("to_nodes")) {
          c.node_links.emplace_back(l.string("node"), l.number("g_W_per_K", Range::positive(limits::kMaxConductance_W_per_K)));
          linkSites.push_back(l);
          l.finish();
        }
      }
      n.finish();
      t.nodes.push_back(c);
    }
    // Node-to-node links name a node of this list (not itself).
    size_t site = 0;
    for (const ThermalNodeConfig& c : t.nodes) {
      for (const auto& link : c.node_links) {
        YamlMap& l = linkSites[site++];
        std::vector<std::string> names;
        for (const ThermalNodeConfig& o : t.nodes)
          if (o.name != c.name) names.push_back(o.name);
        if (std::find(names.begin(), names.end(), link.first) == names.end()) {
          const std::string near = closestMatch(link.first, names);
          throw l.errorAt("node", "no other thermal node named '" + link.first + "'" +
                                      (near.empty() ? "" : " (did you mean '" + near + "'?)"));
        }
      }
    }
  }
  m->finish();
  return t;
}

TimeSeries readAmbient(std::optional<YamlMap> m) {
  if (!m) return TimeSeries::constant(25.0);
  const Range range = Range::closed(-60.0, 100.0);
  if (m->has("temp_C") == m->has("profile")) throw m->error("give exactly one of temp_C or profile");
  TimeSeries ts;
  if (m->has("temp_C")) {
    ts = TimeSeries::constant(m->number("temp_C", range));
  } else {
    YamlMap p = m->map("profile");
    ts.t_s = p.numbers("time_s", Range::nonNegative(limits::kMaxTime_s), 1);
    ts.value = p.numbers("temp_C", range, 1);
    if (ts.t_s.size() != ts.value.size()) throw p.errorAt("temp_C", "needs as many values as time_s");
    for (size_t i = 1; i < ts.t_s.size(); ++i)
      if (!(ts.t_s[i] > ts.t_s[i - 1])) throw p.errorAt("time_s", "values must increase strictly");
    p.finish();
  }
  m->finish();
  return ts;
}

}  // namespace packsim
