// A firmware that failed in a run (issue 28): did not load, broke the contract (ABI,
// init returning non-zero, a task over its budget), crashed or hung -- the host's
// firmware_fault event. Unless the scenario expects it (expect: {firmware_fault: true}),
// `packsim run` exits 1 with this reason and `packsim check` fails with it.
#pragma once
#include <string>

#include "core/scenario/scenario.hpp"
#include "core/sim/result.hpp"

namespace packsim {

// "" when no firmware failed; else "the firmware library '<path>' failed at <t> s:
// <cause>" (or "packsim's core firmware ..."), from the run's first firmware_fault event.
std::string firmwareFailure(const Scenario& s, const RunResult& r);

}  // namespace packsim
