#include "core/sim/scenario_cells.hpp"

namespace packsim {

PackCells scenarioCells(const Scenario& s) {
  return drawCells(s.pack.cell, s.pack.initial_soc, s.pack.series * s.pack.parallel, s.pack.parallel, s.pack.spread,
                   s.pack.cell_overrides, s.run.seed);
}

}  // namespace packsim
