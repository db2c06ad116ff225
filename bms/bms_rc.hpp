// The firmware's 1-RC branch (EkfConfig's r1_mOhm, tau1_s) over one tick: its decay
// exp(-dt / tau1), kept for the last tick length (the tick length seldom changes: an
// expf a tick saved). The EKF's prediction and the coulomb counter's rest anchor
// (bms_soc) each keep one.
#pragma once
#include <math.h>
#include <stdint.h>

namespace bms {

struct RcDecay {
  uint16_t dt_ms;  // the tick length `a` holds the decay of (0: none yet)
  float a;         // exp(-dt / tau1) at dt_ms
};

inline void rcDecayReset(RcDecay& d) {
  d.dt_ms = 0;
  d.a = 0.0f;
}

// exp(-dt / tau1) over dt_ms (0 without a time constant); a tick length above
// 65535 ms is computed each time.
inline float rcDecay(float tau1_s, RcDecay& d, uint32_t dt_ms) {
  if (dt_ms == d.dt_ms && dt_ms != 0) return d.a;
  const float dt_s = static_cast<float>(dt_ms) * 1e-3f;
  const float a = tau1_s > 0.0f ? expf(-dt_s / tau1_s) : 0.0f;
  if (dt_ms <= UINT16_MAX) {
    d.dt_ms = static_cast<uint16_t>(dt_ms);
    d.a = a;
  }
  return a;
}

}  // namespace bms
