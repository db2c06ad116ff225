// Helpers shared by the core tests: inline-YAML scenarios and result queries.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/sim/result.hpp"

namespace packsim::test {

// A one-cell (or N-cell) scenario with constant, simple parameters; `extra` is
// appended YAML (load, bms, run sections …).
std::string simpleCellYaml(int series = 1);
// A 1 A constant load for 10 s, to append to simpleCellYaml().
inline const std::string kSimpleLoadYaml = "load: {current_A: 1}\nrun: {duration_s: 10}\n";
Scenario scenarioFromYaml(const std::string& yaml);
// The message of the ScenarioError `load` throws, or "<no error>".
std::string scenarioErrorOf(const std::function<void()>& load);
// The message of the ScenarioError loading inline YAML (as scenarioFromYaml), or "<no error>".
std::string yamlErrorOf(const std::string& yaml);
// The message of the ScenarioError loading a scenario file, or "<no error>".
std::string fileErrorOf(const std::filesystem::path& file);
// An empty folder `prefix` + `name` under the system temp folder (removed first if there;
// a processTempDir, so removed at exit too).
std::filesystem::path freshTempDir(const std::string& prefix, const std::string& name);
// A folder of this test process under the system temp folder (created, not emptied):
// <tmp>/<name>_<pid>, so concurrent test runs (ctest -j, a sanitizer build) never share one.
// Removed when the process exits normally (kept if PACKSIM_KEEP_TEST_FILES is set).
std::filesystem::path processTempDir(const std::string& name);
// Whether a temporary file of the result `result` (<result>.tmp...) is left in its folder.
bool temporaryOfExists(const std::filesystem::path& result);
// First event of a kind with a detail starting with `detail` (or -1).
double eventTime(const RunResult& r, const std::string& kind, const std::string& detail = "");
// Every event of a kind, in the run's order.
std::vector<const Event*> eventsOf(const RunResult& r, const std::string& kind);
// `text` written to `name` in processTempDir(folder) (created): its path.
std::filesystem::path writeTempFile(const std::string& folder, const std::string& name, const std::string& text);
// Index of the recorded sample at time t (exact tick match).
size_t sampleAt(const Recording& rec, double t);
std::string scenarioDir();
// Passive balancing on a charge with equal capacities: each cell's SOC is the charger's
// charge less its own bleed, so the SOC a cell lost against the cell that bled least
// (which must have bled < 1 As), times the capacity, is the charge its resistor carried:
// to 0.5 % (1 s rectangles; the coulombic efficiency applies to the net current) plus
// slack_As. bleed_As: per series cell, from the recording.
void expectBleedIsTheSocLost(const Recording& rec, const std::vector<double>& bleed_As, double capacity_As,
                             double slack_As);
std::vector<uint8_t> readDatasetBytes(const std::string& file, const std::string& dataset);

}  // namespace packsim::test
