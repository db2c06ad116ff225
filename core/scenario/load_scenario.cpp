#include "core/scenario/load_scenario.hpp"

#include <bms/bms_limits.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/scenario/csv_profile.hpp"
#include "core/scenario/yaml_map.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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

HardwareConfig readHardware(std::optional<YamlMap> hw, const PackConfig& pack) {
  HardwareConfig h;
  // Defaults: a BQ76PL536A-class 14-bit cell ADC, 4 thermistors spread over the
  // string, a 5 mΩ shunt into a gain-10 amplifier on a 16-bit converter.
  h.cell_adc.lsb = 6.25 / 16383.0;
  h.cell_adc.code_max = (1 << 14) - 1;
  h.cell_adc.noise_rms = 0.5e-3;
  h.current_sense.amp_gain = 10.0;
  h.current_sense.noise_A_rms = 0.02;
  const int cells = pack.series;
  for (int k = 0; k < std::min(4, cells); ++k) h.thermistor_cells.push_back(k * cells / std::min(4, cells));
  if (!hw) return h;

  if (auto a = hw->optionalMap("cell_adc")) {
    h.cell_adc.lsb = a->number("lsb_uV", h.cell_adc.lsb * 1e6, Range::positive()) * 1e-6;
    const long bits = a->integer("bits", 14, 8, 24);
    h.cell_adc.code_max = (int64_t{1} << bits) - 1;
    h.cell_adc.gain_error = a->number("gain_error", 0.0, Range::closed(-0.5, 0.5));
    h.cell_adc.offset = a->number("offset_mV", 0.0, Range::closed(-500.0, 500.0)) * 1e-3;
    h.cell_adc.noise_rms = a->number("noise_mV_rms", h.cell_adc.noise_rms * 1e3, Range::closed(0.0, 500.0)) * 1e-3;
    if (h.cell_adc.code_max > 65535) throw a->errorAt("bits", "the BMS reads 16-bit cell codes; allowed 8..16");
    a->finish();
  }
  if (auto t = hw->optionalMap("thermistors")) {
    if (t->has("at_cells")) {
      h.thermistor_cells.clear();
      for (long c : t->integers("at_cells", 1, cells)) h.thermistor_cells.push_back(static_cast<int>(c - 1));
      if (h.thermistor_cells.size() > bms::kMaxThermistors)
        throw t->errorAt("at_cells", "at most " + std::to_string(bms::kMaxThermistors) + " thermistors");
    }
    h.thermistor.r25_ohm = t->number("r25_ohm", h.thermistor.r25_ohm, Range::positive());
    h.thermistor.beta_K = t->number("beta_K", h.thermistor.beta_K, Range::closed(1000.0, 10000.0));
    h.thermistor.pullup_ohm = t->number("pullup_ohm", h.thermistor.pullup_ohm, Range::positive());
    h.thermistor.bits = static_cast<int>(t->integer("bits", 12, 8, 16));
    h.thermistor.noise_codes_rms = t->number("noise_codes_rms", 0.0, Range::closed(0.0, 100.0));
    t->finish();
  }
  if (auto c = hw->optionalMap("current_sense")) {
    CurrentSense& s = h.current_sense;
    s.shunt_ohm = c->number("shunt_ohm", s.shunt_ohm, Range::positive());
    s.amp_gain = c->number("amp_gain", s.amp_gain, Range::positive());
    s.amp_offset_V = c->number("amp_offset_mV", 0.0, Range::closed(-1000.0, 1000.0)) * 1e-3;
    s.gain_error = c->number("gain_error", 0.0, Range::closed(-0.5, 0.5));
    s.noise_A_rms = c->number("noise_A_rms", s.noise_A_rms, Range::nonNegative());
    s.vref_V = c->number("vref_V", s.vref_V, Range::closed(0.5, 10.0));
    s.bits = static_cast<int>(c->integer("bits", 16, 8, 24));
    c->finish();
  }
  hw->finish();
  return h;
}

ProtectionConfig readProtection(YamlMap& parent, const std::string& key, const char* unit, ProtectionConfig d,
                                Range range) {
  auto m = parent.optionalMap(key);
  if (!m) return d;
  const std::string u = unit;
  d.enabled = m->boolean("enabled", d.enabled);
  d.threshold = m->number("threshold_" + u, d.threshold, range);
  d.hysteresis = m->number("hysteresis_" + u, d.hysteresis, Range::nonNegative());
  d.delay_s = m->number("delay_ms", d.delay_s * 1e3, Range::closed(0.0, 600000.0)) * 1e-3;
  m->finish();
  return d;
}

BmsSettings readBms(std::optional<YamlMap> m) {
  BmsSettings b;
  if (!m) return b;
  b.tick_s = static_cast<double>(m->integer("tick_ms", 10, 1, 10000)) * 1e-3;
  if (auto p = m->optionalMap("protections")) {
    b.cell_overvoltage = readProtection(*p, "cell_overvoltage", "V", b.cell_overvoltage, Range::closed(1.0, 5.0));
    b.cell_undervoltage = readProtection(*p, "cell_undervoltage", "V", b.cell_undervoltage, Range::closed(0.5, 4.5));
    b.overcurrent_discharge =
        readProtection(*p, "overcurrent_discharge", "A", b.overcurrent_discharge, Range::positive());
    b.overcurrent_charge = readProtection(*p, "overcurrent_charge", "A", b.overcurrent_charge, Range::positive());
    b.overtemperature = readProtection(*p, "overtemperature", "C", b.overtemperature, Range::closed(0.0, 150.0));
    if (!(b.cell_undervoltage.threshold < b.cell_overvoltage.threshold))
      throw p->error("cell_undervoltage.threshold_V must be below cell_overvoltage.threshold_V");
    p->finish();
  }
  m->finish();
  return b;
}

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

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ScenarioError(path, 0, 0, "", "cannot open scenario file");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

}  // namespace

Scenario loadScenarioText(const std::string& text, const std::string& file, const std::string& base_dir) {
  const YAML::Node root = parseYaml(text, file);
  if (!root || root.IsNull()) throw ScenarioError(file, 1, 1, "", "the scenario is empty");
  YamlMap m(root, file, "");
  Scenario s;
  s.file = file;
  s.text = text;
  s.name = m.string("name", fs::path(file).stem().string());
  s.description = m.string("description", "");
  const uint64_t seed = static_cast<uint64_t>(m.integer("seed", 1, 0, 2147483647L));
  s.pack = readPack(m.map("pack"));
  s.hardware = readHardware(m.optionalMap("hardware"), s.pack);
  s.bms = readBms(m.optionalMap("bms"));
  s.load = readLoad(m.map("load"), base_dir);
  if (auto a = m.optionalMap("ambient")) {
    s.ambient_C = a->number("temp_C", 25.0, Range::closed(-60.0, 100.0));
    a->finish();
  }
  s.run = readRun(m.optionalMap("run"), seed);
  if (auto o = m.optionalMap("output")) {
    s.output.interval_s = o->number("interval_s", 1.0, Range::positive());
    o->finish();
  }
  m.finish();

  // Cross-field checks, reported at the field a user would change.
  if (s.load.isConstant() && s.run.duration_s <= 0.0)
    throw m.errorAt("load", "a constant load needs run.duration_s");
  if (s.output.interval_s < s.bms.tick_s)
    throw m.errorAt("output", "interval_s must be at least the BMS tick (" + std::to_string(s.bms.tick_s) + " s)");
  const double senseRange_A = s.hardware.current_sense.zeroCode() * s.hardware.current_sense.lsb_A();
  for (const auto* p : {&s.bms.overcurrent_discharge, &s.bms.overcurrent_charge}) {
    if (p->enabled && p->threshold >= senseRange_A) {
      std::ostringstream os;
      os << "over-current threshold " << p->threshold << " A is beyond the current sensor's range of +/-"
         << senseRange_A << " A (raise the range with a smaller shunt_ohm or amp_gain)";
      throw m.errorAt("bms", os.str());
    }
  }
  return s;
}

Scenario loadScenarioFile(const std::string& path) {
  const std::string text = slurp(path);
  const std::string dir = fs::path(path).parent_path().string();
  return loadScenarioText(text, path, dir.empty() ? "." : dir);
}

double Scenario::endTime_s() const { return run.duration_s > 0.0 ? run.duration_s : load.duration_s(); }

}  // namespace packsim
