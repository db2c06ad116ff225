// What HardwareSim's parts are actually doing, for records and events (core/sim/hw_*.hpp
// fill it each step).
#pragma once

namespace packsim {

struct HardwareStatus {
  bool relay_closed = false;      // main contact
  bool precharge_closed = false;  // precharge contact
  bool fuse_blown = false;
  bool discharge_fet_on = false;  // gate actually on (after the monitor part's own control)
  bool charge_fet_on = false;
  bool fault_line = false;        // monitor FAULT / ALERT line asserted
  double bus_V = 0.0;
  double precharge_A = 0.0;
  double fet_loss_W = 0.0;
  bool charger_cv = false;        // charger in its constant-voltage phase
  bool charger_done = false;      // charger ended on its taper current
  bool active_safe_state = false; // active balancer: a module out of range, converters off
  bool active_isolated = false;   // ... because the BMS isolated the pack
};

}  // namespace packsim
