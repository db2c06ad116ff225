// HardwareSim's monitor ICs when a library firmware runs (bms.firmware): the
// register-level chain of the scenario's part (models/afe, monitor_part.hpp) instead
// of MonitorStack's pre-built frames. Each tick the chain's analog inputs are filled
// from the same MonitorTruth the stack would see (cells at the pins, injected channel
// errors, thermistors, die = board + die_rise_C, current), scripted comm faults are
// set on its devices, and it advances to t; the firmware then talks to it byte for
// byte over bus 0. Its FAULT line, balancing switches and (BQ76952) FETs drive the
// rest of the hardware. packsim's own core never takes this path.
#pragma once
#include <vector>

#include "core/firmware/monitor_bus.hpp"
#include "models/afe/monitor_stack.hpp"

namespace packsim {

class MonitorChainPath {
 public:
  // Throws std::runtime_error if this build has no register-level model of the part.
  MonitorChainPath(const MonitorConfig& cfg, int cellCount, uint64_t seed);

  void update(double t, const MonitorTruth& truth);
  bool faultLine() const { return bus_.chain->faultLine(); }
  bool balancing(int cell) const;  // series position
  bool dischargeAllowed() const { return bus_.chain->dischargeFetOn(); }
  bool chargeAllowed() const { return bus_.chain->chargeFetOn(); }
  std::vector<MonitorBus*> buses() { return {&bus_}; }

 private:
  MonitorConfig cfg_;
  MonitorBus bus_;
  std::vector<int> firstCell_;  // per device: its bottom cell's series position
};

}  // namespace packsim
