// The cells of a scenario's pack as built: the nominal cell, the seeded spread and the
// explicit per-cell values (models/pack/cell_spread.hpp), from the scenario's seed. The
// plant builds its pack from this, and a batch case records it (core/batch/drawn_inputs.hpp),
// so the values a case reports are the values it ran.
#pragma once
#include "core/scenario/scenario.hpp"
#include "models/pack/cell_spread.hpp"

namespace packsim {

PackCells scenarioCells(const Scenario& s);

}  // namespace packsim
