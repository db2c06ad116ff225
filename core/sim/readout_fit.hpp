// The read-out period of packsim's core firmware, checked against the chain it reads.
//
// One read-out (every device's cells, temperatures and flags) takes bus time: 6
// BQ76PL455A devices on the default 250 kbaud UART need about 12 ms, more than the
// default 10 ms tick. By default the read-out runs every tick (bms.readout.period_ms
// unstated); before t = 0 a probe run measures the longest read-out of the first ticks
// (the same firmware, chain and bus, its budget not enforced) and:
//   - unstated period: the run takes the shortest multiple of the tick that holds it,
//     and says so in a config_warning;
//   - stated period too short: a ScenarioError naming bms.readout.period_ms with the
//     measured time and the shortest period that fits.
// A user's firmware (bms.firmware) sets its own periods and budgets: not probed.
#pragma once
#include <memory>

#include "core/scenario/scenario.hpp"

namespace packsim {

// Null when the scenario runs as it is; else the scenario with its read-out period set.
std::shared_ptr<const Scenario> readoutThatFits(const Scenario& s);

}  // namespace packsim
