// The CLI subcommands as plain functions (testable without a process).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/scenario/load_scenario.hpp"  // bundledScenarioDir

namespace packsim {

struct RunOptions {
  std::string scenario;  // empty: the bundled default
  std::string output;    // empty: packsim-results/<name>.h5
  std::optional<uint64_t> seed;
  bool quiet = false;
};

struct CheckOptions {
  std::vector<std::string> paths;  // files or directories; empty: the bundled scenarios
};

// `packsim plot`: runs `python3 -m packsim.plot` ($PACKSIM_PYTHON overrides python3).
struct PlotOptions {
  std::string result;  // result HDF5 file
  std::string outdir;  // where the PNGs go (created); empty: the current folder
  int dpi = 0;         // 0: packsim.plot's default
};

// `packsim batch`: a sweep (core/batch/sweep.hpp) on a thread pool.
struct BatchCliOptions {
  std::string sweep;       // sweep YAML file
  std::string output_dir;  // empty: the sweep's output_dir
  int threads = 0;         // 0: the sweep's threads, else every core
  bool no_resume = false;  // rerun cases whose result is already complete
  bool quiet = false;
};

// `packsim balance-time` (core/balance/balance_time.hpp).
struct BalanceTimeCliOptions {
  std::string scenario;  // scenario file; or
  std::string preset;    // a bundled scenario by name (scenarios/ or scenarios/balance/)
  std::vector<double> resistors_ohm;
  std::optional<double> delta_Ah, cell_V;
  int high_cells = 1;
  std::optional<double> target_mV;
  double max_hours = 72.0;
  bool analytic_only = false;
  std::string when;          // replace bms.balancing.when (stated in the output)
  bool during_charge = false;
  std::string plot;          // PNG of time and peak board temperature vs R (via Python)
};

// `packsim fit`: the arguments go verbatim to the Python fitter, packsim.__main__ (core/cli/cmd_fit.cpp).
struct FitCliOptions {
  std::vector<std::string> args;
};

std::string defaultScenarioPath();
int cmdRun(const RunOptions& o);
int cmdCheck(const CheckOptions& o);
int cmdPlot(const PlotOptions& o);
int cmdBatch(const BatchCliOptions& o);
int cmdBalanceTime(const BalanceTimeCliOptions& o);
int cmdFit(const FitCliOptions& o);
// Path of a bundled scenario by name; throws std::invalid_argument listing the names.
std::string presetPath(const std::string& name);
// Folder holding the pure-Python `packsim` package ($PACKSIM_PYTHONPATH overrides).
std::string pythonPackageDir();
// `python3 -m MODULE ARGS…` with the package on PYTHONPATH (core/cli/cmd_plot.cpp); its exit code.
int runPythonModule(const std::string& module, std::vector<std::string> args);

}  // namespace packsim
