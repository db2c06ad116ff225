// A condition that must hold for a delay before it counts (a protection's debounce
// timer on a monitor IC): running(t, cond, delay) is true once cond has held
// continuously for delay seconds; a false condition restarts it.
#pragma once

namespace packsim {

struct DebounceTimer {
  double since_s = -1.0;  // time the condition started, -1 = not present

  bool running(double t_s, bool cond, double delay_s) {
    if (!cond) {
      since_s = -1.0;
      return false;
    }
    if (since_s < 0.0) since_s = t_s;
    return t_s - since_s >= delay_s - 1e-9;
  }
  bool present() const { return since_s >= 0.0; }
};

}  // namespace packsim
