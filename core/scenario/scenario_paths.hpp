// Where scenarios and cell presets are looked up, for the command line and the Python
// module alike:
//
//   bundled scenarios   $PACKSIM_SCENARIOS, else the first of <exe>/scenarios and
//                       <exe>/../scenarios holding a cells/ folder (core/io/install_paths.hpp)
//   cell presets        <the scenario's folder>/cells, then <bundled scenarios>/cells
//                       (`cell: {preset: NAME}` reads NAME.yaml from the first that has it)
#pragma once
#include <string>
#include <vector>

namespace packsim {

// Folder of the bundled scenarios; a ScenarioError if there is none.
std::string bundledScenarioDir();
// The bundled scenario named `name` (its file's stem, e.g. "formula_student_96s", or
// "faults/a_estop" by its folder), "" if there is none.
std::string bundledScenarioFile(const std::string& name);
// The bundled scenarios' names (file stems), sorted: for "did you mean" in errors.
std::vector<std::string> bundledScenarioNames();
// The folders a cell preset is searched in, in order, for a scenario in `scenarioDir`.
std::vector<std::string> cellPresetDirs(const std::string& scenarioDir);

}  // namespace packsim
