#include "models/hw/relay.hpp"

namespace packsim {

void relayStepMoving(const RelayConfig& c, RelayState& s, bool coil, bool welded, double t) {
  if (coil != s.coil) {
    s.coil = coil;
    s.coilChanged_s = t;
  }
  const double since = t - s.coilChanged_s;
  if (s.coil && !s.closed && since >= c.close_delay_s - 1e-9) s.closed = true;
  if (!s.coil && s.closed && !welded && since >= c.open_delay_s - 1e-9) s.closed = false;
}

}  // namespace packsim
