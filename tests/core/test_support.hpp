// Helpers shared by the core tests: inline-YAML scenarios and result queries.
#pragma once
#include <string>
#include <vector>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/sim/result.hpp"

namespace packsim::test {

// A one-cell (or N-cell) scenario with constant, simple parameters; `extra` is
// appended YAML (load, bms, run sections …).
std::string simpleCellYaml(int series = 1);
Scenario scenarioFromYaml(const std::string& yaml);
// First event of a kind with a detail starting with `detail` (or -1).
double eventTime(const RunResult& r, const std::string& kind, const std::string& detail = "");
// Index of the recorded sample at time t (exact tick match).
size_t sampleAt(const Recording& rec, double t);
std::string scenarioDir();
std::vector<uint8_t> readDatasetBytes(const std::string& file, const std::string& dataset);

}  // namespace packsim::test
