#include "core/batch/sweep.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/overrides.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/scenario/value_ranges.hpp"
#include "core/scenario/yaml_map.hpp"
#include "models/random/random.hpp"

namespace packsim {

namespace fs = std::filesystem;

uint64_t monteCarloSeed(uint64_t master_seed, uint64_t sample) {
  return deriveSeed(master_seed, sample) & static_cast<uint64_t>(limits::kMaxSeed);  // the scenario's seed range
}

std::string Sweep::resultPath(const SweepCase& c) const { return (fs::path(output_dir) / ("case_" + c.id + ".h5")).string(); }
std::string Sweep::summaryCsvPath() const { return (fs::path(output_dir) / "summary.csv").string(); }

namespace {

// A YAML value as one line of flow-style text, ready to be spliced into a scenario.
std::string flowText(const YAML::Node& n) {
  YAML::Emitter e;
  e.SetMapFormat(YAML::Flow);
  e.SetSeqFormat(YAML::Flow);
  e << n;
  return e.c_str();
}

// One axis of the product: a list of settings, each a set of (key, value) pairs.
using Setting = std::vector<std::pair<std::string, std::string>>;
using Axis = std::vector<Setting>;

void checkKey(YamlMap& m, const YAML::Node& keyNode, const std::string& section, std::vector<std::string>& keys) {
  const std::string key = keyNode.Scalar();
  const std::string field = section + "." + key;
  if (key.empty() || key.front() == '.' || key.back() == '.' || key.find("..") != std::string::npos)
    throw m.errorAt(keyNode, field, "expected a dotted path into the scenario, e.g. pack.cell.capacity_Ah");
  if (std::find(keys.begin(), keys.end(), key) != keys.end())
    throw m.errorAt(keyNode, field, "'" + key + "' is varied twice");
  keys.push_back(key);
}

std::vector<YAML::Node> valueList(YamlMap& m, const YAML::Node& v, const std::string& field) {
  if (!v.IsSequence() || v.size() == 0) throw m.errorAt(v, field, "expected a non-empty list of values");
  std::vector<YAML::Node> out;
  for (size_t i = 0; i < v.size(); ++i) out.push_back(v[i]);
  return out;
}

}  // namespace

// One varied value alone on the base scenario: a value the loader refuses (out of range,
// a wrong type, a key that does not exist) is the sweep's error, at the value's place in
// the sweep file, before any case runs. A combination of values that fails only together
// is that case's failure when it runs (the others finish).
void checkValue(const YamlMap& m, const Sweep& sw, const std::string& key, const YAML::Node& v, const std::string& field) {
  const std::string dir = fs::path(sw.base_path).parent_path().string();
  try {
    loadScenarioWithOverrides(sw.base_text, {{key, flowText(v)}}, sw.base_path, dir.empty() ? "." : dir);
  } catch (const ScenarioError& e) {
    const std::string mark = " (after override " + key + " = ";
    const size_t at = e.message().find(mark);
    if (at == std::string::npos) return;  // not this value's doing
    throw m.errorAt(v, field, (e.field().empty() ? "" : e.field() + ": ") + e.message().substr(0, at) +
                                  " (on the base scenario " + sw.base_path + ")");
  }
}

Sweep loadSweepText(const std::string& text, const std::string& file, const std::string& base_dir, ValueCheck check) {
  const YAML::Node root = parseYaml(text, file);
  if (!root || root.IsNull()) throw ScenarioError(file, 1, 1, "", "the sweep is empty");
  YamlMap m(root, file, "");
  Sweep sw;
  sw.file = file;
  sw.name = m.string("name", file.empty() ? std::string("sweep") : fs::path(file).stem().string());
  fs::path base = m.string("base");
  if (base.is_relative()) base = fs::path(base_dir) / base;
  std::error_code ec;  // a name too long for the file system is "not found", not an exception
  if (!fs::exists(base, ec)) throw m.errorAt("base", "scenario file not found: " + base.string());
  sw.base_path = base.string();
  sw.base_text = readScenarioText(sw.base_path, "base scenario");
  fs::path out = m.string("output_dir", sw.name + "-results");
  if (out.is_relative()) out = fs::path(base_dir) / out;
  sw.output_dir = out.lexically_normal().string();
  sw.threads = static_cast<int>(m.integer("threads", 0, 0, 4096));

  std::vector<Axis> axes;
  if (m.has("grid")) {
    const YAML::Node g = m.node("grid");
    if (!g.IsMap() || g.size() == 0) throw m.errorAt("grid", "expected a mapping of dotted key: [values…]");
    for (auto it = g.begin(); it != g.end(); ++it) {
      checkKey(m, it->first, "grid", sw.keys);
      Axis axis;
      for (const YAML::Node& v : valueList(m, it->second, "grid." + it->first.Scalar())) {
        if (check == ValueCheck::Load) checkValue(m, sw, it->first.Scalar(), v, "grid." + it->first.Scalar());
        axis.push_back({{it->first.Scalar(), flowText(v)}});
      }
      axes.push_back(std::move(axis));
    }
  }
  if (m.has("zip")) {
    const YAML::Node z = m.node("zip");
    if (!z.IsMap() || z.size() == 0) throw m.errorAt("zip", "expected a mapping of dotted key: [values…]");
    Axis axis;
    size_t len = 0;
    std::string first;
    for (auto it = z.begin(); it != z.end(); ++it) {
      checkKey(m, it->first, "zip", sw.keys);
      const std::string key = it->first.Scalar();
      const std::vector<YAML::Node> values = valueList(m, it->second, "zip." + key);
      if (axis.empty()) {
        len = values.size();
        first = key;
        axis.resize(len);
      } else if (values.size() != len) {
        throw m.errorAt(it->second, "zip." + key,
                        "has " + std::to_string(values.size()) + " values but zip." + first + " has " + std::to_string(len));
      }
      for (size_t i = 0; i < len; ++i) {
        if (check == ValueCheck::Load) checkValue(m, sw, key, values[i], "zip." + key);
        axis[i].push_back({key, flowText(values[i])});
      }
    }
    axes.push_back(std::move(axis));
  }
  if (auto mc = m.optionalMap("monte_carlo")) {
    const long samples = mc->integer("samples", 1, 1000000);
    const uint64_t master = static_cast<uint64_t>(mc->integer("master_seed", 0, 0, limits::kMaxSeed));
    mc->finish();
    if (std::find(sw.keys.begin(), sw.keys.end(), "seed") != sw.keys.end())
      throw m.errorAt("monte_carlo", "monte_carlo sets `seed`; do not also vary it in grid or zip");
    sw.keys.push_back("seed");
    Axis axis;
    for (long i = 0; i < samples; ++i)
      axis.push_back({{"seed", std::to_string(monteCarloSeed(master, static_cast<uint64_t>(i)))}});
    axes.push_back(std::move(axis));
  }
  m.finish();
  if (axes.empty()) throw m.error("give at least one of grid, zip or monte_carlo");

  size_t total = 1;
  for (const Axis& a : axes) {
    total *= a.size();
    if (total > 10000000) throw m.error("the sweep expands to more than 10 million cases");
  }
  const int width = std::max<int>(4, static_cast<int>(std::to_string(total - 1).size()));
  for (size_t n = 0; n < total; ++n) {
    SweepCase c;
    c.index = static_cast<int>(n);
    const std::string digits = std::to_string(n);
    c.id = std::string(static_cast<size_t>(std::max(0, width - static_cast<int>(digits.size()))), '0') + digits;
    // Mixed radix, the last axis fastest.
    size_t rest = n;
    std::vector<size_t> pick(axes.size());
    for (size_t a = axes.size(); a-- > 0;) {
      pick[a] = rest % axes[a].size();
      rest /= axes[a].size();
    }
    for (size_t a = 0; a < axes.size(); ++a)
      for (const auto& kv : axes[a][pick[a]]) c.params.push_back(kv);
    sw.cases.push_back(std::move(c));
  }
  return sw;
}

Sweep loadSweepFile(const std::string& path) {
  const std::string text = readScenarioText(path, "sweep file");
  const std::string dir = fs::path(path).parent_path().string();
  return loadSweepText(text, path, dir.empty() ? "." : dir);
}

}  // namespace packsim
