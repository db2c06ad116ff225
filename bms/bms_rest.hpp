// Rest detection shared by the SOC estimate and the balancing policy: the pack rests
// while |I| stays below a threshold; `since_ms` is when the current rest began.
#pragma once
#include <cstdint>

namespace bms {

inline int32_t magnitude(int32_t v) { return v < 0 ? -v : v; }

struct RestTimer {
  bool resting;
  uint32_t since_ms;
};

inline void restReset(RestTimer& r) {
  r.resting = false;
  r.since_ms = 0;
}

// One tick with this current; a rest starts the first tick below the threshold.
inline void restUpdate(RestTimer& r, int32_t current_mA, int32_t restCurrent_mA, uint32_t now_ms) {
  if (magnitude(current_mA) >= restCurrent_mA) {
    r.resting = false;
    return;
  }
  if (!r.resting) {
    r.resting = true;
    r.since_ms = now_ms;
  }
}

// Resting for at least rest_ms.
inline bool restedFor(const RestTimer& r, uint32_t now_ms, uint32_t rest_ms) {
  return r.resting && now_ms - r.since_ms >= rest_ms;
}

}  // namespace bms
