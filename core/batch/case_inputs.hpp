// Whether a batch case's result file is newer than every file the case reads, so that a
// resumed batch may take it as done. The scenario text alone does not say it: the load
// CSV, the base's `extends:` chain, a cell preset, a route, a compare: scenario or a
// firmware library can change under the same text, and a resumed batch then reported
// the old file's summary.
#pragma once
#include <string>
#include <vector>

#include "core/batch/sweep.hpp"
#include "core/scenario/scenario.hpp"

namespace packsim {

// The files a case reads: the base scenario's (core/scenario/scenario_inputs.hpp: the
// file, its compare: scenario and firmware library) and every file its load read
// (Scenario::files_read: the extends: chain, cell presets, the load, route and irradiance
// CSVs, a firmware config_file, a varied value that names one). A preset, route or
// irradiance file edited between runs was not among them, and a resumed batch reported
// the old result.
std::vector<std::string> caseInputFiles(const Sweep& sw, const Scenario& s);

// True when `result` was written after every one of `inputs` was last modified.
bool newerThanInputs(const std::string& result, const std::vector<std::string>& inputs);

}  // namespace packsim
