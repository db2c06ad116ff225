#include "core/batch/case_inputs.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "core/scenario/scenario_inputs.hpp"

namespace packsim {

namespace fs = std::filesystem;

std::vector<std::string> caseInputFiles(const Sweep& sw, const Scenario& s) {
  // The case was loaded from text (its name says which sweep and case): the base file on
  // disk gives the base itself, its compare: scenario and firmware library; every file the
  // load read -- the extends: chain, cell presets, load, route and irradiance CSVs, a
  // varied value naming a file -- is the loader's own list (core/scenario/files_read.hpp).
  Scenario asFile = s;
  asFile.file = sw.base_path;
  std::vector<std::string> files = scenarioInputFiles(asFile);
  for (const std::string& f : s.files_read)
    if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
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
