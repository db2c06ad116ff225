// `packsim plot RESULT.h5 -o DIR`: the figures of packsim.plot as PNG files. The plots
// live in the Python package (python/packsim/plot.py); this runs
// `python3 -m packsim.plot RESULT.h5 -o DIR` with the package on PYTHONPATH, so the
// command line and notebooks draw the very same figures.
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/cli/commands.hpp"
#include "core/scenario/scenario_error.hpp"

extern char** environ;

namespace packsim {

std::string pythonPackageDir() {
  if (const char* env = std::getenv("PACKSIM_PYTHONPATH")) return env;
  return PACKSIM_PYTHON_DIR;
}

// Runs `python3 -m MODULE ARGS…` with the package first on PYTHONPATH; returns its exit code.
int runPythonModule(const std::string& module, std::vector<std::string> moduleArgs) {
  const char* envPython = std::getenv("PACKSIM_PYTHON");
  const std::string python = envPython && *envPython ? envPython : "python3";

  // The package goes first on PYTHONPATH; whatever the user had stays after it.
  std::string path = pythonPackageDir();
  if (const char* old = std::getenv("PYTHONPATH"); old && *old) path += std::string(":") + old;
  setenv("PYTHONPATH", path.c_str(), 1);
  setenv("MPLBACKEND", "Agg", 1);  // files only, never a window

  std::vector<std::string> args = {python, "-m", module};
  args.insert(args.end(), moduleArgs.begin(), moduleArgs.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  pid_t pid = 0;
  const int err = posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ);
  if (err != 0)
    throw std::runtime_error("packsim plot needs Python 3 with numpy, h5py and matplotlib: cannot run '" + python +
                             "' (" + std::strerror(err) + "); install Python 3 or set PACKSIM_PYTHON to an interpreter");
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error(std::string("packsim plot: waitpid failed: ") + std::strerror(errno));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);  // the module printed its own error
  throw std::runtime_error("packsim plot: '" + python + " -m " + module + "' was killed by signal " +
                           std::to_string(WTERMSIG(status)));
}

int cmdPlot(const PlotOptions& o) {
  if (!std::filesystem::is_regular_file(o.result)) throw ScenarioError(o.result, 0, 0, "", "no such result file");
  std::vector<std::string> args = {o.result, "-o", o.outdir.empty() ? "." : o.outdir};
  if (o.dpi > 0) {
    args.push_back("--dpi");
    args.push_back(std::to_string(o.dpi));
  }
  return runPythonModule("packsim.plot", args);
}

}  // namespace packsim
