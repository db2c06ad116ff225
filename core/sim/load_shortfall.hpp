// A power load the pack cannot give: the plant holds it at the pack's maximum power
// point, E²/4R (core/sim/plant.cpp), and the run goes on -- with less energy out than
// the profile asks, which the energy line alone does not tell. Each episode (the ticks
// the pack gave less than asked, in a row) is a `load_limited` event at its end: from
// when to when, the most asked, the most given, and the energy short.
#pragma once
#include <functional>
#include <string>

namespace packsim {

class LoadShortfall {
 public:
  using Sink = std::function<void(double t, const std::string& detail)>;
  // `watch`: a power load from a profile (a current load is always given; the vehicle
  // reports its own limits).
  LoadShortfall(bool watch, double tick_s) : watch_(watch), tick_s_(tick_s) {}

  // One tick: what the load asked (W) and what the pack gave at its terminals (W);
  // `connected`: the relay closed and discharge not blocked (else nothing is asked of it).
  bool watching() const { return watch_; }
  void tick(double t, double asked_W, double gave_W, bool connected, const Sink& event) {
    if (!watch_) return;
    const bool short_ = connected && asked_W > 0.0 && gave_W < asked_W * (1.0 - kTolerance);
    if (short_) note(t, asked_W, gave_W);
    else if (open_) close(t, event);
  }
  // The run's end: an episode still open ends here.
  void finish(double t, const Sink& event) {
    if (open_) close(t, event);
  }

  // Relative shortfall below which the load counts as given: the stable root's rounding
  // is ~1e-15; the maximum power point misses a load past it by its whole excess.
  static constexpr double kTolerance = 1e-6;

 private:
  void note(double t, double asked_W, double gave_W);
  void close(double t, const Sink& event);

  bool watch_;
  double tick_s_;
  bool open_ = false;
  double from_s_ = 0.0, maxAsked_W_ = 0.0, maxGiven_W_ = 0.0, short_J_ = 0.0;
};

}  // namespace packsim
