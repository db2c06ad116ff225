#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "core/cli/commands.hpp"
#include "core/io/hdf5_writer.hpp"
#include "core/scenario/load_scenario.hpp"
#include "core/scenario/overrides.hpp"
#include "core/scenario/scenario_inputs.hpp"
#include "core/scenario/target_switch.hpp"
#include "core/sim/firmware_failure.hpp"
#include "core/sim/run_progress.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/stop_signal.hpp"
#include "core/sim/summary_text.hpp"

namespace packsim {

std::string defaultScenarioPath() { return bundledScenarioDir() + "/eco_marathon_12s.yaml"; }

// A scenario argument: an existing file (or a missing *.yaml, which the loader names),
// else a bundled scenario by name (motorcycle_110s, faults/a_host_dead).
std::string scenarioArgPath(const std::string& arg) {
  if (arg.empty()) return defaultScenarioPath();
  const bool looksLikePath = arg.size() > 5 && arg.compare(arg.size() - 5, 5, ".yaml") == 0;
  if (std::filesystem::exists(arg) || looksLikePath) return arg;  // a missing file: the loader names it
  return presetPath(arg);
}

Overrides parseSetOptions(const std::vector<std::string>& sets) {
  Overrides out;
  for (const std::string& kv : sets) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("--set " + kv + ": expected KEY=VALUE with a dotted scenario key, e.g. "
                                  "--set pack.cell.capacity_Ah=4.5");
    out.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
  }
  return out;
}

int cmdRun(const RunOptions& o) {
  const std::string path = scenarioArgPath(o.scenario);
  Scenario s = loadScenarioOnTarget(path, parseSetOptions(o.set), o.target);
  if (o.seed) s.run.seed = *o.seed;
  const std::string out = o.output.empty() ? "packsim-results/" + s.name + ".h5" : o.output;
  checkResultIsNotAnInput(out, s);  // -o naming the scenario, its extends: chain or its CSV: exit 2
  checkResultPathWritable(out);    // before the run, not after it
  const ResultFileStamp before = resultFileStamp(out);
  // The scenario's warnings (also config_warning events), once the run will start.
  for (const std::string& w : s.warnings) std::cerr << "packsim: warning: " << w << "\n";
  // A bar while it runs when stdout is a terminal (never into a file or a pipe).
  const bool bar = !o.quiet && isatty(fileno(stdout));
  const StopCondition progress = bar ? terminalProgressBar(s.endTime_s(), stdout) : StopCondition{};
  double stoppedAt_s = 0.0;
  const RunResult r = runScenario(s, [&](double t_s, const double* x, const PlantSignals& sig, const bms::Outputs& bo) {
    stoppedAt_s = t_s;
    if (progress) progress(t_s, x, sig, bo);
    return stopSignal() != 0;
  });
  if (bar) terminalProgressDone(stdout);
  if (const int sig = stopSignal()) {
    char at[64];
    std::snprintf(at, sizeof at, "%.3f", stoppedAt_s);
    throw Interrupted(sig, "interrupted by " + stopSignalName(sig) + " at t = " + at + " s; no result written");
  }
  // Another run may have written the same result meanwhile: this complete result
  // replaces it (atomically), and says so.
  const bool replacedAnother = resultFileStamp(out) != before;
  writeResultHdf5(out, s, r);
  if (replacedAnother)
    std::cerr << "packsim: note: another run wrote '" << out << "' while this one ran; it now holds this run's "
              << "complete result (write to separate -o files to keep both)\n";
  if (!o.quiet) std::cout << formatSummary(s, r) << "result          " << out << "\n";
  // A firmware that failed is a failed run, even though the hardware simulation ran on
  // (the result shows what the dead MCU left the pack to), unless the scenario means it.
  if (const std::string failure = firmwareFailure(s, r); !failure.empty() && !s.expect.firmware_fault) {
    std::cerr << "packsim: error: " << failure << "; the run went on with a dead MCU (result kept in '" << out
              << "'); if the scenario means the firmware to fail, say expect: {firmware_fault: true}\n";
    return 1;
  }
  return 0;
}

}  // namespace packsim
