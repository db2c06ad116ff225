// Loads a scenario strictly: unknown keys, wrong types, missing required fields and
// out-of-range values are ScenarioErrors naming file:line:column and the field,
// raised before the run starts. Relative paths (CSV profiles) resolve against the
// scenario file's folder.
#pragma once
#include <memory>
#include <string>

#include "core/scenario/scenario.hpp"
#include "core/scenario/scenario_paths.hpp"  // bundledScenarioDir

namespace YAML {
class Node;
}

namespace packsim {

Scenario loadScenarioFile(const std::string& path);
// The file's text as written (a ScenarioError "cannot open <what>" naming it if it
// cannot be read).
std::string readScenarioText(const std::string& path, const std::string& what = "scenario file");
// `file` names the text in errors; `base_dir` resolves relative CSV paths.
Scenario loadScenarioText(const std::string& text, const std::string& file = "<scenario>",
                          const std::string& base_dir = ".");
// The same from a tree already parsed (and perhaps edited: core/scenario/overrides.hpp);
// errors carry the positions the tree's nodes have. `text` is kept as Scenario::text.
Scenario loadScenarioTree(const YAML::Node& tree, const std::string& text, const std::string& file,
                          const std::string& base_dir);
// The file's YAML with its `extends:` chain merged in, as the loader reads it (relative
// CSV paths of a base re-expressed against this file's folder): one self-contained
// text for `packsim fmu`. Call after loading the file (errors are the loader's).
// `presetDir`, when given, receives the folder its cell preset is looked up from: that of
// the file of the chain that names it.
std::string resolvedScenarioText(const std::string& path, std::string* presetDir = nullptr);
// Keeps `prov` (what the load recorded) with the scenario and computes its warnings
// (core/scenario/scenario_warnings.hpp). The load functions above do this themselves
// unless a caller made its own Provenance active (core/scenario/overrides.cpp).
void attachProvenance(Scenario& s, const std::shared_ptr<Provenance>& prov);

}  // namespace packsim
