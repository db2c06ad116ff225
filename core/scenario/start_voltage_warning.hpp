// A pack that starts past a cell-voltage limit: its cells' open-circuit voltage at
// pack.initial_soc (and pack.cells[].initial_soc) and pack.initial_temp_C, or their
// voltage once the load's first value flows (OCV - I R0 for a current, the same solved
// for a power), below the BMS's under-voltage threshold or the cell's v_min_V, or above
// the over-voltage threshold or v_max_V. The run then trips (or ends its energy count)
// at t = 0: the user is told at load time, with the numbers, rather than by a summary of
// a run that never ran (docs/scenario.md, "Warnings").
#pragma once
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"

namespace packsim {

class Provenance;

void checkStartVoltage(const Scenario& s, const Provenance& p, std::vector<std::string>& out);

}  // namespace packsim
