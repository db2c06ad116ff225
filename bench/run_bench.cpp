// Timing whole runs (macro, scaling) and the fast integrator on its own.
#include <algorithm>
#include <cmath>
#include <vector>

#include "bench/benchmarks.hpp"
#include "core/sim/fast_integrator.hpp"
#include "core/sim/simulation.hpp"

namespace packsim::bench {

RunFigures timeScenario(const std::string& label, const Scenario& s, int runs, int repeats) {
  RunFigures f;
  f.label = label;
  RunResult last;
  f.time = measure(repeats, [&] {
    for (int r = 0; r < runs; ++r) last = runScenario(s);
  });
  // What ran: a run that stops after a trip covers less than the scenario's duration.
  f.sim_s = runs * last.summary.duration_s;
  f.ticks = runs * std::lround(std::floor(last.summary.duration_s / s.bms.tick_s + 1e-9));
  f.cells = last.rec.cells;
  f.solver_steps = runs * last.solver.steps;  // the runs are identical
  f.rhs_evals = runs * last.solver.rhs_evals;
  f.jac_evals = runs * last.solver.jac_evals;
  f.reinits = runs * last.solver.reinits;
  f.lin_setups = runs * last.solver.lin_setups;
  return f;
}

RunFigures timeFastIntegratorOnly(const Scenario& s, int repeats) {
  const Plant plant(s);
  RunFigures f;
  f.label = "fast integrator only";
  f.cells = plant.pack().cellCount();
  f.sim_s = s.endTime_s();
  f.ticks = std::lround(std::floor(f.sim_s / s.bms.tick_s + 1e-9));
  const double tick_s = s.bms.tick_s;
  std::vector<double> x(static_cast<size_t>(plant.stateSize() + kQuadCount), 0.0);
  f.time = measure(repeats, [&] {
    HardwareFaults faults;
    PlantInputs in;
    in.faults = &faults;
    in.relay_closed = true;
    in.load = s.load.segmentAt(0.0);
    FastIntegrator integ(plant, in, FastSettings{s.run.fast_max_substep_s, s.run.fast_substep_fraction});
    std::fill(x.begin(), x.end(), 0.0);
    plant.initialState(x.data());
    integ.reset(0.0, x.data());
    for (long k = 0; k < f.ticks; ++k) {
      const double t_next = static_cast<double>(k + 1) * tick_s;
      double tc = static_cast<double>(k) * tick_s;
      while (tc < t_next) {  // across load breakpoints, as the co-simulation loop does
        const double t_to = std::min(t_next, in.load.t1_s);
        integ.advance(t_to, t_to);
        tc = t_to;
        if (tc >= in.load.t1_s) {
          in.load = s.load.segmentAt(tc);
          integ.reset(tc, integ.state());
        }
      }
    }
    f.solver_steps = integ.stats().steps;
    f.rhs_evals = integ.stats().rhs_evals;
  });
  return f;
}

}  // namespace packsim::bench
