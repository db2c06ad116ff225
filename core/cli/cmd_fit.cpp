// `packsim fit DATA.csv... -o CELL.yaml [options]`: a cell preset fitted to test data. The
// fitter lives in the Python package (python/packsim/fit.py, SciPy); this runs it as
// `python3 -m packsim fit ARGS...` (core/cli/python_module.hpp: the package is found at
// run time, never at a path compiled in) and passes its exit status on: 0 written,
// 2 bad input or a failed fit (nothing written).
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/cli/commands.hpp"
#include "core/cli/python_module.hpp"

namespace packsim {

int cmdFit(const FitCliOptions& o) {
  std::vector<std::string> args = {"fit"};
  args.insert(args.end(), o.args.begin(), o.args.end());
  try {
    return runPythonModule("packsim", args, "the packsim package, NumPy and SciPy");
  } catch (const std::runtime_error& e) {  // no interpreter: the fit cannot run, nothing written
    std::cerr << "packsim fit: error: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace packsim
