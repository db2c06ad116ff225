#include "core/scenario/scenario_paths.hpp"

#include <cstdlib>

#include "core/io/install_paths.hpp"
#include "core/scenario/scenario_error.hpp"

namespace packsim {

std::string bundledScenarioDir() {
  if (const char* env = std::getenv("PACKSIM_SCENARIOS"); env && *env) return env;
  const std::string exe = executableDir();
  const std::string found = firstFolderWith({exe + "/scenarios", exe + "/../scenarios"}, "cells");
  if (found.empty())
    throw ScenarioError("", 0, 0, "", "cannot find the bundled scenarios next to the packsim executable (" +
                        (exe.empty() ? std::string("unknown folder") : exe) +
                        "); set PACKSIM_SCENARIOS to the scenarios folder");
  return found;
}

std::vector<std::string> cellPresetDirs(const std::string& scenarioDir) {
  return {scenarioDir + "/cells", bundledScenarioDir() + "/cells"};
}

}  // namespace packsim
