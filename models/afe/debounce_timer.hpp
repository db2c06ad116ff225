// A condition that must hold for a delay before it counts: the debounce of a monitor
// IC's own protections (comparator delays, protection delays). Time in seconds.
#pragma once

namespace packsim {

struct DebounceTimer {
  double since_s = -1.0;  // when the condition started, -1 = not present

  bool present() const { return since_s >= 0.0; }
  // Updates with the condition at t; true once it has held for delay_s.
  bool held(double t_s, bool condition, double delay_s) {
    if (!condition) {
      since_s = -1.0;
      return false;
    }
    if (since_s < 0.0) since_s = t_s;
    return t_s - since_s >= delay_s - 1e-9;
  }
};

}  // namespace packsim
