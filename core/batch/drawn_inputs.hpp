// The random inputs of a run, as drawn: every cell's parameters as the pack was built
// (core/sim/scenario_cells.hpp: the nominal cell, the seeded spread, the explicit per-cell
// values) and the figures of them that decide a pack's behaviour, per series group (the
// parallel cells of a group share one voltage, so the group is the unit of a string;
// with parallel = 1 a group is a cell):
//
//   drawn_capacity_min_Ah / _max_Ah   smallest / largest group capacity (Σ of its cells):
//                                     the smallest sets the pack's capacity
//   drawn_capacity_rel_sd             sd / mean of the group capacities
//   drawn_r0_scale_max                highest group resistance relative to nominal
//                                     (p / Σ 1/r0_scale): sags and heats most
//   drawn_r0_scale_rel_sd             sd / mean of the group resistances
//   drawn_initial_soc_min / _max      lowest / highest group SOC at the start (charge / capacity)
//   drawn_charge_min_Ah               smallest group charge at the start (Σ soc·capacity):
//                                     the group that empties first on a discharge
//   drawn_headroom_min_Ah             smallest room to full at the start (Σ (1 − soc)·capacity):
//                                     the group that fills first on a charge
//   drawn_self_discharge_max_A        largest group self-discharge current (Σ of its cells)
//   drawn_weakest_group               the group of drawn_charge_min_Ah (1-based; a name, not a quantity)
//
// A batch case writes them to its result file (/inputs: these as attributes, the cells'
// values as datasets) and so to summary.csv, so a Monte Carlo's report can say which
// random input drives an output (docs/batch.md). Same scenario and seed, same values.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "core/scenario/scenario.hpp"

namespace packsim {

struct DrawnInputs {
  int series = 1, parallel = 1;
  std::vector<double> capacity_Ah, r0_scale, initial_soc, self_discharge_A;  // per cell, 1..series×parallel
};

DrawnInputs drawnInputs(const Scenario& s);

// The names of the figures above, in the order listed (summary.csv's column order).
const std::vector<std::string>& drawnInputNames();

// The figures above, in the order listed (weakest group as a number).
std::vector<std::pair<std::string, double>> drawnInputFigures(const DrawnInputs& d);

}  // namespace packsim
