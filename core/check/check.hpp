// Scenarios as regression tests: runs a scenario and judges its `expect:` block, and
// measures the detection latency of every injected fault (the first BMS fault after the
// injection that it can cause, and when the relay opened on it).
#pragma once
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/result.hpp"

namespace packsim {

// One injected fault and how the BMS answered it (the numbers behind a `latencies` line).
struct FaultLatency {
  std::string injected;              // the fault_injected event's detail
  double injected_at_s = 0.0;
  std::string detected_fault;        // first BMS fault at or after the injection that it can cause and no
                                     // later injection took (core/check/fault_causes.hpp); "" if none
  double detection_latency_s = -1.0; // < 0: no such BMS fault followed
  double relay_open_latency_s = -1.0;  // < 0: the relay did not open on it (also: it was already open)
};

struct CheckOutcome {
  std::string name;
  bool passed = false;
  bool error = false;                  // the scenario could not be loaded or run
  std::string error_message;
  std::vector<std::string> failures;   // one line per unmet expectation
  std::vector<std::string> latencies;  // one line per injected fault
  std::vector<FaultLatency> fault_latencies;  // the same, as numbers
  std::string verdict;                 // short summary of what the BMS did
  bool nothing_to_check = false;       // no expect: block (reported "RAN", not "PASS")
  std::vector<std::string> warnings;   // the run's config_warning, monitor_unread, cell_model_range, load_limited, firmware_misuse and register_misuse events
  std::vector<std::string> target;     // target mode: the summary's target lines (cycles, CPU load, stack, resets)
  bool skipped = false;                // --target on a scenario that runs a host-mode library: not run (error_message says why)
};

CheckOutcome judge(const Scenario& s, const RunResult& r);
// Loads, runs and judges one file; never throws (errors become error outcomes). With a
// target (--target), packsim's core runs on it (core/scenario/target_switch.hpp).
CheckOutcome checkScenarioFile(const std::string& path, const std::string& target = "");
// Scenario files under the given files/directories (directories recursively, except
// `cells/` and `profiles/` folders, which hold cell presets and load tables).
std::vector<std::string> collectScenarioFiles(const std::vector<std::string>& paths);

}  // namespace packsim
