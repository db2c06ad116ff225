// Normally-open relay (contactor) with operate and release delays and a welded-contact
// fault. Discrete model advanced once per tick:
//
//   coil energised at t_on  -> contact closes at t_on  + close_delay_s
//   coil released  at t_off -> contact opens  at t_off + open_delay_s  (never, if welded)
//
// A contact that is closed when the weld fault is present stays closed. The
// auxiliary contact mirrors the main contact (mechanically linked).
#pragma once

namespace packsim {

struct RelayConfig {
  double close_delay_s = 0.0;  // datasheet: operate <= 25 ms
  double open_delay_s = 0.0;   // release <= 10 ms
};

struct RelayState {
  bool coil = false;
  bool closed = false;
  double coilChanged_s = 0.0;
};

// Advances the relay to time t with the coil command held since the last call.
// `welded`: the contacts are fused (they cannot open once closed).
// Inline, the settled relay's test: the switchgear steps its two relays every tick, and a
// coil held as before with the contact already where it takes it leaves nothing to do
// (no delay is running: the steps below would change nothing).
void relayStepMoving(const RelayConfig& c, RelayState& s, bool coil, bool welded, double t);
inline void relayStep(const RelayConfig& c, RelayState& s, bool coil, bool welded, double t) {
  if (coil == s.coil && s.closed == coil) return;
  relayStepMoving(c, s, coil, welded, t);
}

}  // namespace packsim
