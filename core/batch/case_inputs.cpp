#include "core/batch/case_inputs.hpp"

#include <filesystem>
#include <system_error>

#include "core/scenario/scenario_inputs.hpp"

namespace packsim {

namespace fs = std::filesystem;

std::vector<std::string> caseInputFiles(const Sweep& sw, const SweepCase& c, const Scenario& s) {
  // The case was loaded from text (its name says which sweep and case); the base file on
  // disk gives the extends: chain and the load CSV as the base names them.
  Scenario asFile = s;
  asFile.file = sw.base_path;
  std::vector<std::string> files = scenarioInputFiles(asFile);
  const fs::path dir = fs::path(sw.base_path).parent_path();
  for (const auto& kv : c.params) {
    std::string v = kv.second;  // flow YAML: a plain or quoted scalar names a file
    if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front()) v = v.substr(1, v.size() - 2);
    if (v.empty() || v.find_first_of("{}[]\n") != std::string::npos) continue;
    std::error_code ec;
    const fs::path p = fs::path(v).is_relative() ? dir / v : fs::path(v);
    if (fs::is_regular_file(p, ec)) files.push_back(p.string());
  }
  return files;
}

bool newerThanInputs(const std::string& result, const std::vector<std::string>& inputs) {
  std::error_code ec;
  const auto written = fs::last_write_time(result, ec);
  if (ec) return false;
  for (const std::string& in : inputs) {
    const auto changed = fs::last_write_time(in, ec);
    if (ec || changed > written) return false;  // unreadable: not known to be older
  }
  return true;
}

}  // namespace packsim
