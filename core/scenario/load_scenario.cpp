#include "core/scenario/load_scenario.hpp"

#include <bms/bms_limits.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/scenario/scenario_sections.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

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
  s.pack = readPack(m.map("pack"), base_dir);
  s.hardware = readHardware(m.optionalMap("hardware"), s.pack);
  s.bms = readBms(m.optionalMap("bms"));
  s.load = readLoad(m.map("load"), base_dir);
  s.ambient_C = readAmbient(m.optionalMap("ambient"));
  s.thermal = readThermal(m.optionalMap("thermal"), s.pack.series * s.pack.parallel);
  s.run = readRun(m.optionalMap("run"), seed);
  if (auto o = m.optionalMap("output")) {
    s.output.interval_s = o->number("interval_s", 1.0, Range::positive());
    o->finish();
  }
  s.faults = readFaults(m, s.pack.series * s.pack.parallel, static_cast<int>(s.hardware.thermistor_cells.size()));
  s.expect = readExpect(m.optionalMap("expect"));
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
