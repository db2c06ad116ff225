#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "core/cli/commands.hpp"
#include "core/io/hdf5_writer.hpp"
#include "core/scenario/load_scenario.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/stop_signal.hpp"
#include "core/sim/summary_text.hpp"

namespace packsim {

std::string defaultScenarioPath() { return bundledScenarioDir() + "/eco_marathon_12s.yaml"; }

int cmdRun(const RunOptions& o) {
  const std::string path = o.scenario.empty() ? defaultScenarioPath() : o.scenario;
  Scenario s = loadScenarioFile(path);
  if (o.seed) s.run.seed = *o.seed;
  const std::string out = o.output.empty() ? "packsim-results/" + s.name + ".h5" : o.output;
  checkResultPathWritable(out);  // before the run, not after it
  double stoppedAt_s = 0.0;
  const RunResult r = runScenario(s, [&](double t_s, const double*, const PlantSignals&, const bms::Outputs&) {
    stoppedAt_s = t_s;
    return stopSignal() != 0;
  });
  if (const int sig = stopSignal()) {
    char at[64];
    std::snprintf(at, sizeof at, "%.3f", stoppedAt_s);
    throw Interrupted(sig, "interrupted by " + stopSignalName(sig) + " at t = " + at + " s; no result written");
  }
  writeResultHdf5(out, s, r);
  if (!o.quiet) std::cout << formatSummary(s, r) << "result          " << out << "\n";
  return 0;
}

}  // namespace packsim
