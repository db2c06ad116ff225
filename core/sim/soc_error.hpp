// How wrong a firmware SOC estimate is against the plant's truth, accumulated tick by
// tick: error = estimate - truth (both 0..1), counted from the first tick the estimate
// is valid. max is the largest |error|, rms over the counted ticks, end the last one.
#pragma once
#include <cmath>

namespace packsim {

struct SocErrorStats {
  double max = 0.0;
  double rms = 0.0;
  double end = 0.0;
  long ticks = 0;
};

class SocErrorTracker {
 public:
  void add(double estimate, double truth) {
    const double e = estimate - truth;
    // std::fmax's value (max is never NaN: a NaN |e| leaves it, as fmax does) without
    // fmax's libm call (some 10 instructions, twice a tick)
    const double a = std::fabs(e);
    st_.max = a > st_.max ? a : st_.max;
    st_.end = e;
    sumSq_ += e * e;
    ++st_.ticks;
  }
  // rms from the sum at the time of asking (not at every tick: a square root per tick)
  SocErrorStats stats() const {
    SocErrorStats s = st_;
    if (s.ticks > 0) s.rms = std::sqrt(sumSq_ / static_cast<double>(s.ticks));
    return s;
  }

 private:
  SocErrorStats st_;
  double sumSq_ = 0.0;
};

}  // namespace packsim
