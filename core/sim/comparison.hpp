// `compare: {scenario: other.yaml}`: the reference scenario is run as well (its own
// seed, without following its own compare:) and the summary states the difference —
// e.g. a cold ride against the same ride at 5 °C: the energy lost and the lower cell
// voltage under load.
#pragma once
#include "core/scenario/scenario.hpp"
#include "core/sim/result.hpp"

namespace packsim {

// Runs s.compare_scenario and fills r.summary.compare (nothing without one).
void compareWithReference(const Scenario& s, RunResult& r);

}  // namespace packsim
