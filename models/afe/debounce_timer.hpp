// A condition that must hold for a delay before it counts (a protection comparator's
// debounce): `held(t, cond, delay_s)` is true once `cond` has been true continuously
// for delay_s; a false `cond` restarts it. Times in s, evaluated at the caller's steps.
#pragma once

namespace packsim {

struct DebounceTimer {
  double since_s = -1.0;  // time the condition started, -1 = not present

  bool active() const { return since_s >= 0.0; }
  bool held(double t_s, bool cond, double delay_s) {
    if (!cond) {
      since_s = -1.0;
      return false;
    }
    if (since_s < 0.0) since_s = t_s;
    return t_s - since_s >= delay_s - 1e-9;
  }
};

}  // namespace packsim
