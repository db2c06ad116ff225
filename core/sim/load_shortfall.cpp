#include "core/sim/load_shortfall.hpp"

#include <algorithm>
#include <cstdio>

namespace packsim {

void LoadShortfall::note(double t, double asked_W, double gave_W) {
  if (!open_) {
    open_ = true;
    from_s_ = t;
    maxAsked_W_ = maxGiven_W_ = short_J_ = 0.0;
  }
  maxAsked_W_ = std::max(maxAsked_W_, asked_W);
  maxGiven_W_ = std::max(maxGiven_W_, gave_W);
  short_J_ += (asked_W - gave_W) * tick_s_;  // each tick's shortfall held over the tick
}

void LoadShortfall::close(double t, const Sink& event) {
  open_ = false;
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "%.2f-%.2f s: the pack gave less power than the load asked (at most %.0f W while up to %.0f W was "
                "asked): it was held at its maximum power point, about %.2f Wh short of the profile",
                from_s_, t, maxGiven_W_, maxAsked_W_, short_J_ / 3600.0);
  event(t, buf);
}

}  // namespace packsim
