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
  const std::string text = readScenarioText(scenarioPath);
  YAML::Node root = YAML::Load(text);
  const fs::path baseDir = fs::path(scenarioPath).parent_path();
  for (const char* key : {"extends", "compare"})
    if (root[key])
      throw errorAt(scenarioPath, root[key], key,
                    std::string("packsim fmu cannot pack a scenario with `") + key +
                        ":` yet; write the scenario out in one file");
  FmuResources out;
  if (root["load"] && root["load"].IsMap() && root["load"]["csv"]) packLoadCsv(root["load"], baseDir, out);
  if (root["pack"] && root["pack"]["cell"] && root["pack"]["cell"].IsMap() && root["pack"]["cell"]["preset"])
    packCellPreset(root["pack"]["cell"], baseDir, out);
  YAML::Emitter e;
  e << root;
  out["scenario.yaml"] = std::string(e.c_str()) + "\n";
  return out;
}

}  // namespace packsim
