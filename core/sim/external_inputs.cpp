#include "core/sim/external_inputs.hpp"

#include <limits>

namespace packsim {

bool ExternalInputs::applySome(double t, PlantInputs& pin) const {
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

}  // namespace packsim
