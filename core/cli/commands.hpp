// The CLI subcommands as plain functions (testable without a process).
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/cli/bundled_catalog.hpp"    // presetPath, bundledCatalog
#include "core/scenario/load_scenario.hpp"
#include "core/scenario/overrides.hpp"
#include "core/scenario/scenario_paths.hpp"  // bundledScenarioDir

namespace packsim {

struct RunOptions {
  std::string scenario;  // a file or a bundled scenario's name; empty: the bundled default
  std::vector<std::string> set;  // --set KEY=VALUE overrides (dotted keys, YAML values)
  std::string output;    // empty: packsim-results/<name>.h5
  std::optional<uint64_t> seed;
  bool quiet = false;
  std::string target;    // --target cortex-m4: packsim's core as ARM code (core/scenario/target_switch.hpp)
};

// `packsim show`: the scenario's values with their origins, and its warnings.
struct ShowOptions {
  std::string scenario;          // a file or a bundled scenario's name; empty: the bundled default
  std::vector<std::string> set;  // --set KEY=VALUE overrides
  std::string format = "text";   // text | yaml | json
};

struct CheckOptions {
  std::vector<std::string> paths;  // files or directories; empty: the bundled scenarios
  std::string target;              // --target cortex-m4: every scenario with packsim's core on the target
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

// `packsim export` (python/packsim/export.py).
struct ExportOptions {
  std::string result;  // result HDF5 file
  std::string format;  // csv, mat or parquet
  std::string output;  // empty: next to the result, by format
};

// `packsim report` (python/packsim/report.py).
struct ReportOptions {
  std::string source;  // result HDF5 file or batch folder
  std::string output;  // HTML file
};

// `packsim fmu` (core/cli/cmd_fmu.cpp, docs/fmu.md).
struct FmuCliOptions {
  std::string scenario;  // a file or a bundled scenario's name
  std::string output;    // the .fmu to write
  bool quiet = false;
};

std::string defaultScenarioPath();
int cmdList();
int cmdReport(const ReportOptions& o);
int cmdExport(const ExportOptions& o);
int cmdRun(const RunOptions& o);
int cmdShow(const ShowOptions& o);
// --set KEY=VALUE arguments as overrides (std::invalid_argument on one without '=').
Overrides parseSetOptions(const std::vector<std::string>& sets);
// A scenario argument as a path: an existing file, else a bundled scenario by name.
std::string scenarioArgPath(const std::string& arg);
int cmdCheck(const CheckOptions& o);
int cmdPlot(const PlotOptions& o);
int cmdBatch(const BatchCliOptions& o);
int cmdBalanceTime(const BalanceTimeCliOptions& o);
int cmdFit(const FitCliOptions& o);
int cmdFmu(const FmuCliOptions& o);
// Folder holding the pure-Python `packsim` package ($PACKSIM_PYTHONPATH overrides).
std::string pythonPackageDir();

}  // namespace packsim
