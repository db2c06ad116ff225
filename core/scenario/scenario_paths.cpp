#include "core/scenario/scenario_paths.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

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

namespace {

// Every bundled scenario file (cell presets under cells/ are not scenarios).
std::vector<std::filesystem::path> bundledScenarioFiles() {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(bundledScenarioDir(), ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (it->is_regular_file() && it->path().extension() == ".yaml" && it->path().parent_path().filename() != "cells")
      files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

std::string bundledScenarioFile(const std::string& name) {
  namespace fs = std::filesystem;
  if (name.empty()) return "";
  const fs::path dir = bundledScenarioDir();
  std::error_code ec;
  if (name.find('/') != std::string::npos && fs::is_regular_file(dir / (name + ".yaml"), ec))
    return (dir / (name + ".yaml")).string();
  for (const fs::path& f : bundledScenarioFiles())
    if (f.stem() == name) return f.string();
  return "";
}

std::vector<std::string> bundledScenarioNames() {
  std::vector<std::string> names;
  for (const auto& f : bundledScenarioFiles()) names.push_back(f.stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> cellPresetDirs(const std::string& scenarioDir) {
  return {scenarioDir + "/cells", bundledScenarioDir() + "/cells"};
}

}  // namespace packsim
