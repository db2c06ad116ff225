#include "core/cli/bundled_catalog.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/scenario_error.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

// The first sentence of the file's leading comment block, on one line.
std::string commentDescription(const fs::path& file) {
  std::ifstream in(file);
  std::string line, text;
  while (std::getline(in, line) && line.rfind('#', 0) == 0) {
    const size_t start = line.find_first_not_of("# ");
    if (start == std::string::npos) break;
    text += (text.empty() ? "" : " ") + line.substr(start);
  }
  while (!text.empty() && (text.back() == ' ' || text.back() == '\r')) text.pop_back();
  const size_t stop = text.find(". ");
  if (stop != std::string::npos) text.erase(stop);
  if (!text.empty() && text.back() == '.') text.pop_back();
  return text;
}

std::string scenarioDescription(const fs::path& file) {
  try {
    const YAML::Node doc = YAML::LoadFile(file.string());
    if (doc.IsMap() && doc["description"] && doc["description"].IsScalar()) return doc["description"].as<std::string>();
  } catch (const YAML::Exception&) {  // a broken bundled file still lists, described by its comment
  }
  return commentDescription(file);
}

}  // namespace

std::vector<CatalogEntry> bundledCatalog() {
  const fs::path dir = bundledScenarioDir();
  std::vector<CatalogEntry> scenarios, cells;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file() || e.path().extension() != ".yaml") continue;
    const bool isCell = e.path().parent_path().filename() == "cells";
    if (isCell)
      cells.push_back({"cell", e.path().stem().string(), e.path().string(), commentDescription(e.path())});
    else
      scenarios.push_back({"scenario", e.path().stem().string(), e.path().string(), scenarioDescription(e.path())});
  }
  auto byName = [](const CatalogEntry& a, const CatalogEntry& b) { return a.name < b.name; };
  std::sort(scenarios.begin(), scenarios.end(), byName);
  std::sort(cells.begin(), cells.end(), byName);
  scenarios.insert(scenarios.end(), cells.begin(), cells.end());
  return scenarios;
}

std::string presetPath(const std::string& name) {
  const std::string stem = name.size() > 5 && name.compare(name.size() - 5, 5, ".yaml") == 0
                               ? name.substr(0, name.size() - 5) : name;
  if (std::string path = bundledScenarioFile(stem); !path.empty()) return path;
  const std::vector<std::string> names = bundledScenarioNames();
  std::string known;
  for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
  const std::string near = closestMatch(stem, names);
  throw std::invalid_argument("no bundled scenario named '" + name + "'" +
                              (near.empty() ? "" : "; did you mean '" + near + "'?") + " (known: " + known + ")");
}

}  // namespace packsim
