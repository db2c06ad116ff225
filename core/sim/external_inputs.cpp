#include "core/sim/external_inputs.hpp"

#include <limits>

namespace packsim {

bool ExternalInputs::applyToPlant(double t, PlantInputs& pin) const {
  bool changed = false;
  if (load_A_or_W) {
    const LoadSegment& l = pin.load;
    const bool held = l.slope_A_per_s == 0.0 && l.i0_A == *load_A_or_W &&
                      l.t1_s == std::numeric_limits<double>::infinity();
    if (!held) {
      pin.load = LoadSegment{t, std::numeric_limits<double>::infinity(), *load_A_or_W, 0.0};
      changed = true;
    }
  }
  if (ambient_C && pin.ambient_C != ambient_C) {
    pin.ambient_C = ambient_C;
    changed = true;
  }
  return changed;
}

void ExternalInputs::applyToPins(bms::Inputs& in) const {
  if (estop_internal_pulled) in.eSwitchInternal = *estop_internal_pulled;
  if (estop_external_pulled) in.eSwitchExternal = *estop_external_pulled;
  if (charger_present) in.chargerPresent = *charger_present;
}

}  // namespace packsim
