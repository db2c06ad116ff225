// `packsim fit DATA.csv... -o CELL.yaml [options]`: a cell preset fitted to test data. The
// fitter lives in the Python package (python/packsim/fit.py, SciPy); this runs it as
// `python3 -c <bootstrap> fit ARGS...` and passes its exit status on (0 written, 2 bad
// input or a failed fit, nothing written).
//
// The package is found at run time, never at a path compiled in: the environment as it
// is ($PACKSIM_PYTHONPATH, then $PYTHONPATH), then <exe_dir>/python and
// <exe_dir>/../python (the build tree puts the package in <build>/python next to
// <build>/packsim). $PACKSIM_PYTHON names the interpreter (default python3).
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "core/cli/commands.hpp"

extern char** environ;

namespace packsim {

namespace fs = std::filesystem;

namespace {

// Imports the package's command runner; without the package, NumPy or SciPy: one line, exit 2.
constexpr const char* kBootstrap =
    "import sys\n"
    "try:\n"
    "    import numpy, scipy.optimize\n"
    "    from packsim.__main__ import main\n"
    "except ImportError as e:\n"
    "    sys.stderr.write('packsim fit: error: needs Python 3 with the packsim package, NumPy and SciPy '\n"
    "                     '(bash scripts/install-deps.sh, or pip install numpy scipy): %s\\n' % e)\n"
    "    sys.exit(2)\n"
    "sys.exit(main(sys.argv[1:]))\n";

// Folders next to the running executable that hold a `packsim` package.
std::vector<std::string> packageDirsNearExecutable() {
  std::vector<std::string> dirs;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return dirs;
  for (const fs::path& dir : {exe.parent_path() / "python", exe.parent_path().parent_path() / "python"})
    if (fs::is_regular_file(dir / "packsim" / "__init__.py", ec)) dirs.push_back(fs::weakly_canonical(dir, ec).string());
  return dirs;
}

std::string fitPythonPath() {
  std::string path;
  auto add = [&path](const std::string& p) {
    if (!p.empty()) path += (path.empty() ? "" : ":") + p;
  };
  if (const char* env = std::getenv("PACKSIM_PYTHONPATH")) add(env);
  if (const char* env = std::getenv("PYTHONPATH")) add(env);
  for (const std::string& dir : packageDirsNearExecutable()) add(dir);
  return path;
}

}  // namespace

int cmdFit(const FitCliOptions& o) {
  const char* envPython = std::getenv("PACKSIM_PYTHON");
  const std::string python = envPython && *envPython ? envPython : "python3";
  setenv("PYTHONPATH", fitPythonPath().c_str(), 1);
  setenv("MPLBACKEND", "Agg", 1);  // the report is a file, never a window

  std::vector<std::string> args = {python, "-c", kBootstrap, "fit"};
  args.insert(args.end(), o.args.begin(), o.args.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  pid_t pid = 0;
  if (const int err = posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ); err != 0) {
    std::cerr << "packsim fit: error: needs Python 3 with NumPy and SciPy: cannot run '" << python << "' ("
              << std::strerror(err) << "); install Python 3 or set PACKSIM_PYTHON to an interpreter\n";
    return 2;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      std::cerr << "packsim fit: error: waitpid failed: " << std::strerror(errno) << "\n";
      return 1;
    }
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);  // the fitter printed its own report or error
  std::cerr << "packsim fit: error: '" << python << "' was killed by signal " << WTERMSIG(status) << "\n";
  return 1;
}

}  // namespace packsim
