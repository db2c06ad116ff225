// The MCU's outputs over time: every change of its output pins (relay, precharge,
// FETs, charger enable) and of the charger DAC, at the instant on the MCU clock the
// firmware wrote it (tick start + the bus time, delays and, in target mode, the code's
// cycles before the write). The firmware host records the changes; the simulation loop
// applies each at its instant (core/sim/simulation.hpp: the tick's actuation takes
// those at or before t_k, the plant's advance stops at the later ones).
#pragma once
#include <bms/bms_hal.hpp>

#include <cstdint>
#include <deque>
#include <limits>

#include "core/sim/same_instant.hpp"

namespace packsim {

struct PinLevels {
  bool relay = false, precharge = false, dischargeFet = false, chargeFet = false, chargerEnable = false;
  int32_t chargerCurrent_mA = 0;
  bool operator==(const PinLevels& o) const {
    return relay == o.relay && precharge == o.precharge && dischargeFet == o.dischargeFet &&
           chargeFet == o.chargeFet && chargerEnable == o.chargerEnable && chargerCurrent_mA == o.chargerCurrent_mA;
  }
  bool operator!=(const PinLevels& o) const { return !(*this == o); }
};

inline PinLevels pinsOf(const bms::Outputs& o) {
  return {o.relayClose, o.prechargeClose, o.dischargeFetOn, o.chargeFetOn, o.chargerEnable, o.chargerCurrentRequest_mA};
}

inline void applyPins(bms::Outputs& o, const PinLevels& p) {
  o.relayClose = p.relay;
  o.prechargeClose = p.precharge;
  o.dischargeFetOn = p.dischargeFet;
  o.chargeFetOn = p.chargeFet;
  o.chargerEnable = p.chargerEnable;
  o.chargerCurrentRequest_mA = p.chargerCurrent_mA;
}

struct PinChange {
  double t_s;
  PinLevels pins;  // every output's level from t_s on
};

// The changes not yet in effect, in time order, and the levels in effect now.
class PinTimeline {
 public:
  void push(const PinChange& c) {
    PinChange k = c;
    if (!pending_.empty() && k.t_s < pending_.back().t_s) k.t_s = pending_.back().t_s;  // one clock: never backwards
    pending_.push_back(k);
  }
  // The levels in effect at t: every change at or before t (up to rounding) applied.
  const PinLevels& at(double t_s) {
    while (!pending_.empty() && reached(t_s, pending_.front().t_s)) {
      now_ = pending_.front().pins;
      pending_.pop_front();
    }
    return now_;
  }
  // The instant of the next change not yet in effect (+inf: none).
  double next_s() const { return pending_.empty() ? std::numeric_limits<double>::infinity() : pending_.front().t_s; }

 private:
  std::deque<PinChange> pending_;
  PinLevels now_;
};

}  // namespace packsim
