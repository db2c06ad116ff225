#include "core/sim/comparison.hpp"

#include "core/scenario/load_scenario.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"

namespace packsim {

void compareWithReference(const Scenario& s, RunResult& r) {
  if (s.compare_scenario.empty()) return;
  Scenario ref = loadScenarioFile(s.compare_scenario);
  ref.compare_scenario.clear();  // one level: a reference's own reference is not run
  const RunResult rr = runScenario(ref);
  Comparison& c = r.summary.compare;
  c.present = true;
  c.name = ref.name;
  c.energy_delivered_Wh = rr.summary.energy_delivered_Wh;
  c.losses_Wh = rr.quad[kQuadChemEnergy_J] / 3600.0 - rr.summary.energy_delivered_Wh;
  c.min_cell_V = rr.summary.min_cell_V;
  c.this_losses_Wh = r.quad[kQuadChemEnergy_J] / 3600.0 - r.summary.energy_delivered_Wh;
}

}  // namespace packsim
