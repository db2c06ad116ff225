// The files a loaded scenario was read from: the scenario file, every file of its
// `extends:` chain, the load CSV, the `compare:` scenario and a firmware library. A
// result path must not name one of them (`packsim run -o`, docs/results.md).
#pragma once
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"

namespace packsim {

// Paths as the scenario names them (resolved against the folder of the file that
// names them); files that no longer exist are left out.
std::vector<std::string> scenarioInputFiles(const Scenario& s);

// Throws std::invalid_argument "the result file '<out>' is <what> '<input>' ..." when
// `out` names one of the scenario's inputs (the same file, through any path or link).
void checkResultIsNotAnInput(const std::string& out, const Scenario& s);

}  // namespace packsim
