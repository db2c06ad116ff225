// `packsim plot RESULT.h5 -o DIR`: the figures of packsim.plot as PNG files. The plots
// live in the Python package (python/packsim/plot.py); this runs
// `python3 -m packsim.plot RESULT.h5 -o DIR` (core/cli/python_module.hpp), so the
// command line and notebooks draw the very same figures.
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/cli/commands.hpp"
#include "core/cli/python_module.hpp"
#include "core/io/install_paths.hpp"
#include "core/scenario/scenario_error.hpp"

namespace packsim {

std::string pythonPackageDir() {
  if (const char* env = std::getenv("PACKSIM_PYTHONPATH"); env && *env) return env;
  const std::string exe = executableDir();
  return firstFolderWith({exe + "/python", exe + "/../.."}, "packsim/__init__.py");  // "": the interpreter's own
}

int cmdPlot(const PlotOptions& o) {
  if (!std::filesystem::is_regular_file(o.result)) throw ScenarioError(o.result, 0, 0, "", "no such result file");
  std::vector<std::string> args = {o.result, "-o", o.outdir.empty() ? "." : o.outdir};
  if (o.dpi > 0) {
    args.push_back("--dpi");
    args.push_back(std::to_string(o.dpi));
  }
  return runPythonModule("packsim.plot", args, "numpy, h5py and matplotlib");
}

}  // namespace packsim
