// Runs a sweep's cases on a pool of threads (one scenario per thread at a time):
//
//   for each case, by whichever worker is free:
//     text = applyOverrides(base, case.params)         core/scenario/overrides.hpp
//     if <output_dir>/case_<id>.h5 exists, holds this very scenario text and its drawn
//          inputs: skip (resume)
//     else load strictly, run, write the HDF5 with the drawn inputs (/inputs,
//          core/batch/drawn_inputs.hpp; written to a temporary name and renamed, so a
//          file that exists is complete); an exception becomes the case's error
//   then <output_dir>/summary.csv: one row per case — id, the varied parameters,
//   status (ok | failed), the /inputs attributes (drawn_*), every /summary attribute of
//   its result file, error, file.
//
// A failing case never stops the others. Progress goes to `progress` (a bar with ETA
// when it is a terminal, one line per finished case otherwise).
#pragma once
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "core/batch/sweep.hpp"

namespace packsim {

struct BatchOptions {
  int threads = 0;            // 0: the sweep's `threads`, else every core
  bool resume = true;         // false: rerun every case
  std::FILE* progress = stdout;  // nullptr: silent
  // Each case in its own forked process (core/batch/case_processes.hpp): a crashing case
  // is recorded as failed and the others finish. `packsim batch` sets it; same results.
  bool isolate = false;
};

struct CaseOutcome {
  bool ok = false;
  bool skipped = false;       // result already complete (resume)
  double wall_s = 0.0;        // time to run it (0 when skipped)
  std::string error;
  std::vector<std::pair<std::string, std::string>> summary;  // /summary attributes as text
};

struct BatchReport {
  int total = 0, ok = 0, failed = 0, skipped = 0;
  int threads = 0;
  double wall_s = 0.0;
  std::string csv_path;
  std::vector<CaseOutcome> cases;  // in sweep order
};

BatchReport runBatch(const Sweep& sweep, const BatchOptions& options);

// One case exactly as runBatch runs it (resume check, load, run, write, read back the
// summary); never throws. For engines that schedule cases themselves (Python on Dask).
CaseOutcome runSweepCase(const Sweep& sweep, const SweepCase& c, bool resume);

// <output_dir>/summary.csv from outcomes in sweep order (as runBatch writes it).
void writeSummaryCsv(const Sweep& sweep, const BatchReport& report);

// Reads the /inputs (a batch case's drawn inputs) and /summary attributes of a result
// file as (name, text), in that order;
// empty if the file is not a complete packsim result. `scenario_yaml` receives the
// root attribute of the same name.
std::vector<std::pair<std::string, std::string>> readResultSummary(const std::string& path, std::string* scenario_yaml);

// One CSV field, quoted when it holds a comma, quote or line break (RFC 4180).
std::string csvField(const std::string& s);

}  // namespace packsim
