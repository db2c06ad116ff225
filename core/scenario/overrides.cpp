#include "core/scenario/overrides.hpp"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <filesystem>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/provenance.hpp"
#include "core/scenario/scenario_warnings.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/scenario/yaml_map.hpp"
#include "core/scenario/yaml_layers.hpp"

namespace packsim {

namespace {

// One step of a dotted path: a mapping key or a 0-based list index.
struct PathStep {
  std::string key;
  bool is_index = false;
  size_t index = 0;
};

bool allDigits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  return true;
}

size_t toIndex(const std::string& digits, const std::string& file, const std::string& key) {
  if (!allDigits(digits) || digits.size() > 9)
    throw ScenarioError(file, 0, 0, key, "override key: '" + digits + "' is not a list index (0, 1, 2, ...)");
  return static_cast<size_t>(std::stoul(digits));
}

// "pack.cell.rc_pairs.0.r_ohm" and "pack.cell.rc_pairs[0].r_ohm" -> steps.
std::vector<PathStep> parsePath(const std::string& key, const std::string& file) {
  if (key.empty()) throw ScenarioError(file, 0, 0, key, "override key is empty");
  std::vector<PathStep> steps;
  size_t start = 0;
  while (true) {
    const size_t dot = key.find('.', start);
    std::string part = key.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (part.empty()) throw ScenarioError(file, 0, 0, key, "override key has an empty component");
    const size_t bracket = part.find('[');
    const std::string name = part.substr(0, bracket);
    if (!name.empty()) {
      if (allDigits(name)) steps.push_back({name, true, toIndex(name, file, key)});
      else steps.push_back({name, false, 0});
    } else if (bracket == std::string::npos || bracket != 0 || steps.empty()) {
      throw ScenarioError(file, 0, 0, key, "override key has an empty component");
    }
    // Any number of [i] suffixes.
    size_t pos = bracket;
    while (pos != std::string::npos && pos < part.size()) {
      const size_t close = part.find(']', pos);
      if (part[pos] != '[' || close == std::string::npos)
        throw ScenarioError(file, 0, 0, key, "override key: unbalanced '[' in '" + part + "'");
      const std::string digits = part.substr(pos + 1, close - pos - 1);
      steps.push_back({digits, true, toIndex(digits, file, key)});
      pos = close + 1;
    }
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return steps;
}

// The field name the scenario loader would use for this path: "a.b[0].c".
std::string loaderFieldName(const std::vector<PathStep>& steps) {
  std::string f;
  for (const PathStep& s : steps) {
    if (s.is_index) f += "[" + std::to_string(s.index) + "]";
    else f += (f.empty() ? "" : ".") + s.key;
  }
  return f;
}

std::string prefixName(const std::vector<PathStep>& steps, size_t count) {
  return loaderFieldName(std::vector<PathStep>(steps.begin(), steps.begin() + static_cast<long>(count)));
}

const char* kindOf(const YAML::Node& n) {
  if (!n.IsDefined()) return "not set";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a mapping";
  if (n.IsScalar()) return "a single value";
  return "empty";
}

ScenarioError errorAtNode(const std::string& file, const YAML::Node& n, const std::string& key, const std::string& msg) {
  const YAML::Mark m = n.Mark();
  const bool known = m.line >= 0;
  return ScenarioError(file, known ? m.line + 1 : 0, known ? m.column + 1 : 0, key, msg);
}

YAML::Node parseValue(const std::string& key, const std::string& value, const std::string& file) {
  try {
    return YAML::Load(value);
  } catch (const YAML::ParserException& e) {
    throw ScenarioError(file, 0, 0, key, "override value '" + value + "' is not valid YAML: " + e.msg);
  }
}

void applyOne(YAML::Node& root, const std::string& key, const std::string& value, const std::string& file) {
  const std::vector<PathStep> steps = parsePath(key, file);
  const YAML::Node v = parseValue(key, value, file);
  YAML::Node cur;
  cur.reset(root);  // reset() rebinds; operator= would overwrite the node it refers to
  for (size_t i = 0; i < steps.size(); ++i) {
    const PathStep& s = steps[i];
    const bool last = i + 1 == steps.size();
    const std::string here = prefixName(steps, i);
    if (s.is_index) {
      if (!cur.IsSequence())
        throw errorAtNode(file, cur, key, (here.empty() ? "the scenario" : here) + " is " + kindOf(cur) +
                                              ", not a list: cannot take element [" + std::to_string(s.index) + "]");
      if (s.index >= cur.size())
        throw errorAtNode(file, cur, key, here + " has " + std::to_string(cur.size()) + " element(s); index " +
                                              std::to_string(s.index) + " is out of range");
      if (last) {
        cur[s.index] = v;
        return;
      }
      YAML::Node next = cur[s.index];
      cur.reset(next);
    } else {
      if (!(cur.IsMap() || cur.IsNull() || !cur.IsDefined()))  // missing keys are created
        throw errorAtNode(file, cur, key, (here.empty() ? "the scenario" : here) + " is " + kindOf(cur) +
                                              ", not a mapping: cannot set '" + s.key + "' inside it");
      if (last) {
        const YAML::Node before = static_cast<const YAML::Node&>(cur)[s.key];  // const: must not add the key
        // `--set KEY=null` removes the key (yaml_layers.hpp): its default applies, or
        // the other key of a choice can be given.
        if (removesKey(v)) {
          // Over a base (`extends:`) the null stays in this layer, where the merge removes
          // the base's key too; alone, the key goes (a null left there would be an error).
          if (root["extends"]) cur[s.key] = v;
          else if (before) cur.remove(s.key);
          return;
        }
        if (Provenance* p = Provenance::active(); p && before && (before.IsMap() || before.IsSequence()) && v.IsScalar())
          p->warn(dependenceRemovedWarning(loaderFieldName(steps), before, nodePlace(Provenance::displayName(file), before), v,
                                          "--set " + key + "=" + value));
        YAML::Node layer(YAML::NodeType::Map);
        layer[s.key] = v;
        dropReplacedAlternatives(cur, layer, here);  // `--set ambient.profile=...` drops ambient.temp_C
        cur[s.key] = v;
        return;
      }
      YAML::Node next = cur[s.key];
      cur.reset(next);
    }
  }
}

// True when the loader's `field` and an override's field name sit on one branch of
// the tree (equal, or one inside the other).
bool related(const std::string& field, const std::string& overridden) {
  if (field.empty() || overridden.empty()) return false;
  auto under = [](const std::string& inner, const std::string& outer) {
    return inner.size() > outer.size() && inner.compare(0, outer.size(), outer) == 0 &&
           (inner[outer.size()] == '.' || inner[outer.size()] == '[');
  };
  return field == overridden || under(field, overridden) || under(overridden, field);
}

// The scenario's tree with every override applied in place: nodes the overrides do not
// replace keep their line and column in the original text.
YAML::Node overriddenTree(const std::string& yamlText, const Overrides& overrides, const std::string& file) {
  YAML::Node root = parseYaml(yamlText, file);
  if (!root || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw errorAtNode(file, root, "", "the scenario is not a mapping of key: value pairs");
  for (const auto& [key, value] : overrides) applyOne(root, key, value, file);
  return root;
}

// The overridden scenario as text: what ran, kept with the results (comments dropped).
std::string emitted(const YAML::Node& root, const std::string& file) {
  YAML::Emitter out;
  out << root;
  if (!out.good()) throw ScenarioError(file, 0, 0, "", "cannot write the overridden scenario: " + out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

}  // namespace

std::string applyOverrides(const std::string& yamlText, const Overrides& dottedKeyToYamlValue,
                           const std::string& fileForErrors) {
  if (dottedKeyToYamlValue.empty()) return yamlText;
  return emitted(overriddenTree(yamlText, dottedKeyToYamlValue, fileForErrors), fileForErrors);
}

Scenario loadScenarioWithOverrides(const std::string& yamlText, const Overrides& overrides, const std::string& file,
                                   const std::string& base_dir) {
  if (overrides.empty()) return loadScenarioText(yamlText, file, base_dir);
  const auto prov = std::make_shared<Provenance>(file);
  Provenance::Scope scope(prov.get());
  for (const auto& [key, value] : overrides) prov->addOverride(loaderFieldName(parsePath(key, file)), key + "=" + value);
  const YAML::Node root = overriddenTree(yamlText, overrides, file);
  try {
    Scenario s = loadScenarioTree(root, emitted(root, file), file, base_dir);
    attachProvenance(s, prov);
    return s;
  } catch (const ScenarioError& e) {
    // A value an override put in has no position in the file: an error on a field an
    // override touched is that override's; report it so. A Python dict scenario arrives
    // as overrides on an empty one (file "<dict>"): its keys are the user's scenario, not
    // overrides of one, so the value is named as given.
    const char* how = file == kDictScenarioName ? " (given as " : " (after override ";
    for (auto it = overrides.rbegin(); it != overrides.rend(); ++it) {
      if (related(e.field(), loaderFieldName(parsePath(it->first, file))))
        throw ScenarioError(file, 0, 0, e.field(), e.message() + how + it->first + " = " + it->second + ")");
    }
    throw;  // an untouched field: the tree kept its position in the original text
  }
}

Scenario loadScenarioFileWithOverrides(const std::string& path, const Overrides& overrides) {
  const std::string text = readScenarioText(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return loadScenarioWithOverrides(text, overrides, path, dir.empty() ? "." : dir);
}

}  // namespace packsim
