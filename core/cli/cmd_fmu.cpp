// `packsim fmu SCENARIO -o pack.fmu`: the scenario's pack, hardware and BMS firmware as
// an FMI 2.0 co-simulation FMU (docs/fmu.md). The archive holds modelDescription.xml
// (from the variable table, core/fmu/fmu_variables.hpp), binaries/linux64/packsim_fmu.so
// (found next to this executable, or $PACKSIM_FMU_BINARY) and resources/ (the scenario
// and the files it references, core/fmu/fmu_resources.hpp).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <stdexcept>

#include "core/cli/commands.hpp"
#include "core/fmu/fmu_archive.hpp"
#include "core/fmu/fmu_resources.hpp"
#include "core/fmu/model_description.hpp"
#include "core/io/install_paths.hpp"
#include "core/scenario/scenario_error.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

std::string fmuBinaryPath() {
  if (const char* env = std::getenv("PACKSIM_FMU_BINARY"); env && *env) return env;
  return executableDir() + "/" + kFmuModelIdentifier + ".so";
}

// The packed resources loaded from a scratch folder: proves them self-contained and
// gives the scenario the FMU's library will see.
Scenario loadPacked(const FmuResources& res) {
  std::random_device rd;
  const fs::path dir = fs::temp_directory_path() / ("packsim-fmu-" + std::to_string(rd()));
  struct Cleanup {
    fs::path d;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(d, ec);
    }
  } cleanup{dir};
  for (const auto& [name, bytes] : res) {
    const fs::path p = dir / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << bytes;
  }
  return loadScenarioFile((dir / "scenario.yaml").string());
}

}  // namespace

int cmdFmu(const FmuCliOptions& o) {
  const std::string path = scenarioArgPath(o.scenario);
  loadScenarioFile(path);  // every scenario error, named in the user's own file
  const FmuResources res = collectFmuResources(path);
  const Scenario s = loadPacked(res);
  const std::string binary = fmuBinaryPath();
  if (!fs::is_regular_file(binary))
    // Not the scenario's fault but the installation's: a failed run (exit 1), not bad input.
    throw std::runtime_error(binary + ": the FMU library was not built (the build needs the FMI headers from "
                             "`pip install fmpy`); or set PACKSIM_FMU_BINARY");
  FmuArchive a;
  const std::string& text = res.at("scenario.yaml");
  a.contents["modelDescription.xml"] = modelDescriptionXml(s, fmuVariables(s), fmuGuid(text));
  for (const auto& [name, bytes] : res) a.contents["resources/" + name] = bytes;
  a.files[std::string("binaries/linux64/") + kFmuModelIdentifier + ".so"] = binary;
  writeFmuArchive(a, o.output);
  if (!o.quiet) std::cout << "wrote " << o.output << " (" << s.name << ", BMS tick " << s.bms.tick_s << " s)\n";
  return 0;
}

}  // namespace packsim
