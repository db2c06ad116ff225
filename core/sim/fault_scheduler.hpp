// Plays a scenario's `faults:` script: at each tick it starts injections whose time
// has come or whose condition on the plant's truth first holds, ends those whose
// duration is over, and rewrites the HardwareFaults the models read. Every start and
// end becomes an event.
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"
#include "core/sim/fault_effect.hpp"
#include "core/sim/hardware_faults.hpp"
#include "core/sim/plant.hpp"

namespace packsim {

class RunTracker;

class FaultScheduler {
 public:
  FaultScheduler(const Scenario& s, const Plant& plant);

  // Updates `faults` for tick t. Returns true when an input of the plant's ODE changed
  // (extra load, cell heat, internal short), so the integrator must restart.
  // (Inline: a run with no injection left to start or end -- most runs, every tick --
  // returns at once instead of calling, some 30 instructions a tick.)
  bool update(double t, const double* x, const PlantSignals& sig, HardwareFaults& faults, RunTracker& tracker) {
    return pending_ > 0 && updatePending(t, x, sig, faults, tracker);
  }
  // The earliest instant after t at which a timed injection starts or ends (infinity if
  // none): the loop stops the integrators there, wherever it falls within a tick.
  // Injections on a condition are judged at the ticks.
  double nextChange_s(double t) const {
    return pending_ > 0 ? nextPendingChange_s(t) : std::numeric_limits<double>::infinity();
  }
  // Sizes and clears `faults` (everything healthy) before the first tick.
  void reset(HardwareFaults& faults) const { apply(faults); }
  // At the end of a run (t_end_s: the last tick): one `fault_not_reached` event for
  // every injection that never started, saying when it was due and why the run ended
  // first (`run_end`: "the run's duration", "the trip stopped it", ...).
  void reportUnreached(double t_end_s, const std::string& run_end, RunTracker& tracker) const;
  // The current path over the next interval, while an over-current, charger or weld
  // injection is active and has not yet acted (core/sim/fault_effect.hpp): one branch a
  // tick otherwise (the caller builds the PathState only when watching()).
  bool watching() const { return watching_; }
  void noteEffects(const PathState& p);
  // At the end of a run: one `fault_no_effect` event for every such injection that
  // started before t_end_s and never acted.
  void reportNoEffect(double t_end_s, RunTracker& tracker) const;

 private:
  bool updatePending(double t, const double* x, const PlantSignals& sig, HardwareFaults& faults, RunTracker& tracker);
  double nextPendingChange_s(double t) const;
  double quantity(Quantity q, double t, const double* x, const PlantSignals& sig) const;
  void apply(HardwareFaults& f) const;
  double activeFor_s(const FaultInjection& inj) const;
  // Injection i is active, acts through the current path, and has not acted yet.
  bool waitingToAct(size_t i) const;
  bool anyWaitingToAct() const;

  struct Track {
    double start_s = -1.0;
    bool active = false;
    bool done = false;
    double end_s = -1.0;  // removed at (-1: still active, or never started)
    EffectSeen seen;
  };
  const Scenario& s_;
  const Plant& plant_;
  std::vector<Track> state_;
  bool watching_ = false;  // anyWaitingToAct(), kept where it can change
  size_t pending_;  // injections not done (to start, or to end): with none, no tick has anything to do
};

}  // namespace packsim
