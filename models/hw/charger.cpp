#include "models/hw/charger.hpp"

#include <algorithm>

namespace packsim {

double chargerCurrent_A(double limit_A, double setpoint_V, double e_V, double r_ohm) {
  if (!(limit_A > 0.0)) return 0.0;
  if (!(r_ohm > 0.0)) return e_V < setpoint_V ? limit_A : 0.0;
  return std::clamp((setpoint_V - e_V) / r_ohm, 0.0, limit_A);
}

double chargerStep(const ChargerConfig& c, ChargerState& s, bool enable, double request_A, double charge_A,
                   double pack_V, double setpoint_V) {
  if (!c.present || !enable) {
    s = ChargerState{};
    return 0.0;
  }
  const double limit = std::min(c.current_A, std::max(0.0, request_A));
  if (s.enabled && !s.done) {
    // CV: held below the limit by the setpoint (a blocked path leaves the voltage below it).
    s.cv = pack_V >= setpoint_V - 1e-3 && charge_A < limit - 1e-9;
    if (s.cv && charge_A < c.end_current_A) s.done = true;
  }
  s.enabled = true;
  return s.done ? 0.0 : limit;
}

}  // namespace packsim
