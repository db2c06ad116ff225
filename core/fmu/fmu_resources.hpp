// What an FMU carries in resources/ so it runs without the scenario's folder: the
// scenario (its `extends:` chain merged in, re-emitted with its file references pointing
// inside resources/) and every file it references: the load CSV (profiles/<name>) and a
// cell preset (cells/<name>.yaml). A scenario with `compare:` (a second, reference run)
// is refused with a ScenarioError naming the key.
#pragma once
#include <map>
#include <string>

namespace packsim {

// Relative path inside resources/ -> file contents. "scenario.yaml" is the scenario.
using FmuResources = std::map<std::string, std::string>;

FmuResources collectFmuResources(const std::string& scenarioPath);

}  // namespace packsim
