#include "core/fmu/fmu_resources.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/scenario_error.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

ScenarioError errorAt(const std::string& file, const YAML::Node& n, const std::string& field, const std::string& msg) {
  const YAML::Mark m = n.Mark();
  return ScenarioError(file, m.line + 1, m.column + 1, field, msg);
}

// The load CSV: copied to profiles/<its name>, the scenario pointed there.
void packLoadCsv(YAML::Node load, const fs::path& baseDir, FmuResources& out) {
  YAML::Node ref = load["csv"].IsMap() ? load["csv"]["file"] : load["csv"];
  fs::path csv = ref.as<std::string>();
  if (csv.is_relative()) csv = baseDir / csv;
  const std::string inside = "profiles/" + csv.filename().string();
  out[inside] = readScenarioText(csv.string(), "load CSV");
  ref = inside;
}

// A cell preset: the file the loader would take (the scenario's cells/ folder first,
// then the bundled one), copied to cells/<name>.yaml where the loader looks first.
void packCellPreset(const YAML::Node& cell, const fs::path& baseDir, FmuResources& out) {
  const std::string name = cell["preset"].as<std::string>();
  for (const fs::path& dir : {baseDir / "cells", fs::path(bundledScenarioDir()) / "cells"}) {
    std::error_code ec;
    const fs::path p = dir / (name + ".yaml");
    if (fs::exists(p, ec)) {
      out["cells/" + name + ".yaml"] = readScenarioText(p.string(), "cell preset");
      return;
    }
  }
}

}  // namespace

FmuResources collectFmuResources(const std::string& scenarioPath) {
  std::string presetDir;  // a base's own cells/ preset is found in the base's folder
  YAML::Node root = YAML::Load(resolvedScenarioText(scenarioPath, &presetDir));  // `extends:` merged in
  const fs::path baseDir = fs::path(scenarioPath).parent_path();
  if (root["compare"]) {
    const std::string why = "packsim fmu cannot pack a scenario with a `compare:` reference run; remove it for the FMU";
    const YAML::Node own = YAML::Load(readScenarioText(scenarioPath));
    if (own["compare"]) throw errorAt(scenarioPath, own["compare"], "compare", why);
    throw ScenarioError(scenarioPath, 0, 0, "compare", why + " (it comes with `extends:`)");
  }
  FmuResources out;
  if (root["load"] && root["load"].IsMap() && root["load"]["csv"]) packLoadCsv(root["load"], baseDir, out);
  if (root["pack"] && root["pack"]["cell"] && root["pack"]["cell"].IsMap() && root["pack"]["cell"]["preset"])
    packCellPreset(root["pack"]["cell"], presetDir, out);
  YAML::Emitter e;
  e << root;
  out["scenario.yaml"] = std::string(e.c_str()) + "\n";
  return out;
}

}  // namespace packsim
