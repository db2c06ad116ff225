#include "models/hw/fuse.hpp"

#include <algorithm>
#include <limits>

namespace packsim {

void fuseStep(const FuseConfig& c, FuseState& s, double current_A, double dt_s) {
  if (!c.present || s.blown) return;
  const double hold = c.hold_ratio * c.rated_A;
  s.q_A2s = std::max(0.0, s.q_A2s + (current_A * current_A - hold * hold) * dt_s);
  if (s.q_A2s >= c.i2t_A2s) s.blown = true;
}

double fuseBlowTime_s(const FuseConfig& c, double current_A) {
  const double hold = c.hold_ratio * c.rated_A;
  const double excess = current_A * current_A - hold * hold;
  return excess > 0.0 ? c.i2t_A2s / excess : std::numeric_limits<double>::infinity();
}

}  // namespace packsim
