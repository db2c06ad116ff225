// Whether a batch case's result file is newer than every file the case reads, so that a
// resumed batch may take it as done. The scenario text alone does not say it: the load
// CSV, the base's `extends:` chain, a compare: scenario or a firmware library can change
// under the same text, and a resumed batch then reported the old file's summary.
#pragma once
#include <string>
#include <vector>

#include "core/batch/sweep.hpp"
#include "core/scenario/scenario.hpp"

namespace packsim {

// The files case `c` reads: the base scenario's inputs (core/scenario/scenario_inputs.hpp:
// the file, its extends: chain, its load CSV; the case's compare: scenario and firmware
// library) and any varied value that names an existing file beside the base (a grid over
// load.csv). Cell preset files are not among them.
std::vector<std::string> caseInputFiles(const Sweep& sw, const SweepCase& c, const Scenario& s);

// True when `result` was written after every one of `inputs` was last modified.
bool newerThanInputs(const std::string& result, const std::vector<std::string>& inputs);

}  // namespace packsim
