// The benchmarks bench/main.cpp runs; each returns its figures for one table.
//
//   floor     the bare per-cell arithmetic (bench/floor_kernel.hpp) over a pack's cells
//   macro     system D (110s1p) for one hour of racing: three back-to-back runs of the
//             bundled 20-minute race, with CVODE and with the fast integrator
//   scaling   12 … 5,000 cells of system D's cell and race (bench_support scaledPack)
//   batch     the same cases through core/batch with 1 and with 2 threads
//
// A "cell-step" is one cell advanced over one BMS tick (10 ms here).
#pragma once
#include <string>
#include <vector>

#include "bench/bench_support.hpp"

namespace packsim::bench {

// ns per cell-step of the floor kernel on scenario s's pack, its tick as the step,
// the load's current, for `ticks` steps (minimum of `repeats`).
struct FloorResult {
  double cpu_ns_per_cell_step = 0.0;
  double wall_ns_per_cell_step = 0.0;
  double checksum = 0.0;
};
FloorResult runFloor(const Scenario& s, long ticks, int repeats);

struct RunFigures {
  std::string label;
  int cells = 0;
  double sim_s = 0.0;
  long ticks = 0;
  Timing time;
  long solver_steps = 0, rhs_evals = 0, jac_evals = 0, reinits = 0, lin_setups = 0;
  double cpuNsPerCellStep() const { return time.cpu_s * 1e9 / (static_cast<double>(cells) * static_cast<double>(ticks)); }
  double wallNsPerCellStep() const { return time.wall_s * 1e9 / (static_cast<double>(cells) * static_cast<double>(ticks)); }
};
// Whole runs (runScenario: setup, loop, recording): `runs` back-to-back runs make one
// figure (their times add up); the figure is repeated `repeats` times, minimum kept.
RunFigures timeScenario(const std::string& label, const Scenario& s, int runs, int repeats);

// The fast integrator alone on a scenario's plant: relay closed, the load profile,
// one advance per tick, no BMS, no sensors, no recording.
RunFigures timeFastIntegratorOnly(const Scenario& s, int repeats);

// Batch: `cases` Monte Carlo cases of a scenario text (fast solver), 1 vs 2 threads.
struct BatchFigures {
  int cases = 0;
  double wall1_s = 0.0, wall2_s = 0.0;
  double cores1 = 0.0, cores2 = 0.0;  // process CPU time / wall time: cores actually obtained
  double cpu1_s = 0.0, cpu2_s = 0.0;  // process CPU time: equal when the threads do not interfere
  double load_before = 0.0, load_after = 0.0;
  bool all_ok = false;
};
// Alternates 1 and 2 threads `repeats` times and keeps each one's minimum.
BatchFigures runBatchBench(int cases, double duration_s, int repeats);

}  // namespace packsim::bench
