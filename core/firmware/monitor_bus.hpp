// One MCU bus to a monitor chain, shared by the hardware side (which fills the chain's
// analog inputs and advances it at each tick) and the firmware host (whose transfers
// happen at the MCU's clock, inside or after the tick). The chain only ever moves
// forward in time: a task that ran past the next tick leaves the chain where it was.
#pragma once
#include <memory>

#include "models/afe/monitor_part.hpp"

namespace packsim {

struct MonitorBus {
  std::unique_ptr<MonitorChain> chain;
  double time_s = 0.0;  // the chain has advanced to here
  void advanceTo(double t_s) {
    if (t_s > time_s) time_s = t_s;
    chain->advance(time_s);
  }
};

}  // namespace packsim
