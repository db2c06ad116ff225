// Runs `python3 -m MODULE ARGS...` with the packsim package first on PYTHONPATH, for
// the subcommands whose work lives in Python (plot, export, report): the command line
// and notebooks then draw and convert with the very same code.
//
// The interpreter is $PACKSIM_PYTHON (the `packsim` console script sets it to its own
// interpreter), else python3 on PATH. The package folder is pythonPackageDir().
#pragma once
#include <string>
#include <vector>

namespace packsim {

// The module's exit status; throws std::runtime_error if Python cannot be started
// (`needs` says what the command needs, for the message).
int runPythonModule(const std::string& module, const std::vector<std::string>& args, const std::string& needs);

}  // namespace packsim
