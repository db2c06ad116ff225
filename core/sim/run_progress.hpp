// Progress of one long run, reported through runScenario's per-tick StopCondition
// (which only reads, so a run with progress is the same run): `report(t_s, end_s)` is
// called each time simulated time passes another `step_fraction` of the run (and at
// most every tick), never stopping it. The CLI draws a terminal bar with it
// (terminalProgressBar); the Python binding forwards it to a callback (tqdm).
#pragma once
#include <cstdio>
#include <functional>

#include "core/sim/simulation.hpp"

namespace packsim {

StopCondition progressCondition(double end_s, std::function<void(double t_s, double end_s)> report,
                                double step_fraction = 0.01);

// A bar rewritten in place on `out` (a terminal): "[#####-----]  52%  624 / 1200 s".
// terminalProgressDone clears it.
StopCondition terminalProgressBar(double end_s, std::FILE* out);
void terminalProgressDone(std::FILE* out);

}  // namespace packsim
