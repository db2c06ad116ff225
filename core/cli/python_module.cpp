#include "core/cli/python_module.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "core/cli/commands.hpp"

extern char** environ;

namespace packsim {

int runPythonModule(const std::string& module, const std::vector<std::string>& moduleArgs, const std::string& needs) {
  const char* envPython = std::getenv("PACKSIM_PYTHON");
  const std::string python = envPython && *envPython ? envPython : "python3";

  // The package goes first on PYTHONPATH; whatever the user had stays after it.
  std::string path = pythonPackageDir();
  if (const char* old = std::getenv("PYTHONPATH"); old && *old) path += (path.empty() ? "" : ":") + std::string(old);
  if (!path.empty()) setenv("PYTHONPATH", path.c_str(), 1);
  setenv("MPLBACKEND", "Agg", 1);  // files only, never a window

  std::vector<std::string> args = {python, "-m", module};
  args.insert(args.end(), moduleArgs.begin(), moduleArgs.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  pid_t pid = 0;
  const int err = posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ);
  if (err != 0)
    throw std::runtime_error("this command needs Python 3 with " + needs + ": cannot run '" + python + "' (" +
                             std::strerror(err) + "); install Python 3 or set PACKSIM_PYTHON to an interpreter");
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error(std::string("waitpid failed: ") + std::strerror(errno));
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);  // the module printed its own error
  throw std::runtime_error("'" + python + " -m " + module + "' was killed by signal " +
                           std::to_string(WTERMSIG(status)));
}

}  // namespace packsim
