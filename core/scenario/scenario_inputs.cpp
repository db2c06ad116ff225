#include "core/scenario/scenario_inputs.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/scenario/yaml_map.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

struct Input {
  std::string path;
  std::string what;  // "the scenario", "a file of its extends: chain", ...
};

fs::path resolved(const fs::path& dir, const std::string& rel) {
  const fs::path p(rel);
  return p.is_relative() ? dir / p : p;
}

bool fileExists(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
}

// The CSV a scenario's own text names (load.csv: FILE or {file: FILE}), if any.
std::string csvOf(const YAML::Node& root) {
  if (!root.IsMap() || !root["load"] || !root["load"].IsMap() || !root["load"]["csv"]) return "";
  const YAML::Node csv = root["load"]["csv"];
  if (csv.IsScalar()) return csv.Scalar();
  if (csv.IsMap() && csv["file"] && csv["file"].IsScalar()) return csv["file"].Scalar();
  return "";
}

// Whether a scenario's text could name another file: an extends: or csv key. In UTF-8 a
// key holds these letters unless a double-quoted escape spells it ("\x65xtends"); a
// UTF-16 or UTF-32 file (which YAML reads too) has NUL bytes. Text with neither word, no
// backslash and no NUL names no file and is not parsed (the YAML of a long load table,
// some 12 million instructions, each time the result file exists).
bool mayNameFiles(const std::string& text) {
  return text.find("extends") != std::string::npos || text.find("csv") != std::string::npos ||
         text.find('\\') != std::string::npos || text.find('\0') != std::string::npos;
}

std::vector<Input> inputs(const Scenario& s) {
  std::vector<Input> out;
  if (s.file.empty()) return out;
  out.push_back({s.file, "the scenario"});
  // Follow the extends: chain as the loader did (each file relative to its own folder);
  // every file of it, and a CSV any of them names, relative to the naming file.
  fs::path file(s.file);
  for (int depth = 0; depth < 64; ++depth) {
    YAML::Node root;
    try {
      std::ifstream in(file, std::ios::binary);
      std::stringstream buffer;
      buffer << in.rdbuf();
      const std::string text = buffer.str();
      if (!mayNameFiles(text)) break;
      root = YAML::Load(text);
    } catch (const std::exception&) {
      break;  // the loader read it: unreachable in practice
    }
    const fs::path dir = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    if (const std::string csv = csvOf(root); !csv.empty() && fileExists(resolved(dir, csv)))
      out.push_back({resolved(dir, csv).string(), "the load CSV"});
    if (!root.IsMap() || !root["extends"] || !root["extends"].IsScalar()) break;
    file = resolved(dir, root["extends"].Scalar());
    if (!fileExists(file)) break;
    out.push_back({file.string(), "a file of its extends: chain"});
  }
  if (!s.compare_scenario.empty() && fileExists(s.compare_scenario))
    out.push_back({s.compare_scenario, "the compare: scenario"});
  if (s.bms.firmware.library && fileExists(s.bms.firmware.library_path))
    out.push_back({s.bms.firmware.library_path, s.bms.firmware.isTarget() ? "the firmware ELF" : "the firmware library"});
  return out;
}

}  // namespace

std::vector<std::string> scenarioInputFiles(const Scenario& s) {
  std::vector<std::string> files;
  for (const Input& i : inputs(s)) files.push_back(i.path);
  return files;
}

void checkResultIsNotAnInput(const std::string& out, const Scenario& s) {
  if (!fileExists(out)) return;  // every input exists: a new file cannot be one of them
  for (const Input& i : inputs(s)) {
    std::error_code ec;
    if (fs::equivalent(out, i.path, ec))
      throw std::invalid_argument("the result file '" + out + "' is " +
                                  (fs::equivalent(i.path, s.file, ec) ? std::string("the scenario file itself")
                                                                      : i.what + " '" + i.path + "' of scenario '" +
                                                                            s.file + "'") +
                                  "; writing the result there would destroy it (choose another -o)");
  }
}

}  // namespace packsim
