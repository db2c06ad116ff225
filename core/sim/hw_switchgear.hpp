// HardwareSim's switchgear: the main relay and the precharge relay (operate and release
// delays, weld), the FET pair, the fuse (I²t) and the load bus behind them (precharge RC,
// bleed-down). The MCU's pins and the monitor part's own FET drivers come in as a
// SwitchDrive; what conducts goes out into the plant's inputs (PlantInputs).
// The FET gates take the MCU's pin, the part's driver, or both, as hardware.fet_control
// wires them (models/hw/mosfet.hpp, fetGateOn).
//
//   tick(t, dt)        the fuse heats with the tick's current, the relays and gates move,
//                      the bus follows the pack, charges through the precharge path, or
//                      bleeds down, over the tick
//   atPin(t, tEnd)     inside a tick, the instant the MCU changed a pin: relays and gates
//                      act from t on; a precharge path that starts conducting is solved over
//                      [t, tEnd); the fuse and the bus on an idle path stay on the tick's step
#pragma once
#include "core/scenario/scenario.hpp"
#include "core/sim/hardware_faults.hpp"
#include "core/sim/hw_status.hpp"
#include "core/sim/plant.hpp"
#include "models/hw/fuse.hpp"
#include "models/hw/relay.hpp"

namespace packsim {


// The lines into the switchgear at an instant: the MCU's output pins and the monitor part's
// own FET drivers (a part without FETs: both true), with the monitor FAULT line.
struct SwitchDrive {
  bool relayPin = false, prechargePin = false;  // MCU relay coil drives
  bool dischargePin = false, chargePin = false; // MCU FET gate pins
  bool afeDischarge = true, afeCharge = true;   // the monitor part's DSG / CHG drivers
  bool faultLine = false;                       // monitor FAULT / ALERT line asserted
};

// What the switchgear presents to the plant.
struct SwitchState {
  bool mainClosed = false;  // the main relay closed and the fuse intact
  bool dsg = false, chg = false;  // the FET gates actually on
  bool dischargeBlocked = false, chargeBlocked = false;
  double precharge_A = 0.0;  // mean precharge current over the rest of the tick
};

class HwSwitchgear {
 public:
  explicit HwSwitchgear(const HardwareConfig& hw);

  // The tick's step at t (dt = the tick).
  SwitchState tick(double t, double dt, const SwitchDrive& d, const HardwareFaults& f, const PlantSignals& sig);
  // A pin change at t inside the tick ending at tEnd; `held` is what the plant runs on now.
  SwitchState atPin(double t, double tEnd, const SwitchDrive& d, const HardwareFaults& f, const PlantSignals& sig,
                    const PlantInputs& held);
  // The next instant after t at which a relay contact moves on its own; +inf when none.
  double nextSwitch_s(double t) const;
  // Writes the state into the plant's inputs; true when one of them changed. `fetHeats`:
  // the FETs heat a thermal node (their gates are then inputs of the plant too).
  static bool apply(const SwitchState& s, bool fetHeats, PlantInputs& pin);
  // The relay, precharge, fuse, gate, bus and FET-loss fields of the status.
  void report(const SwitchState& s, const PlantSignals& sig, HardwareStatus& st) const;

  bool relayClosed() const { return relay_.closed; }  // the auxiliary contact follows it
  bool relayCoil() const { return relay_.coil; }       // driven (the MCU's pin, unless the FAULT line opens it)
  double bus_V() const { return bus_V_; }

 private:
  // The relays stepped to t and the FET gates and paths as the lines set them. Every tick
  // and pin change, and mostly with the lines as before and the relays at rest: then what
  // it gave last time (gatesAnew would change nothing and give the same), no relay step,
  // gate or path decided again.
  SwitchState gates(double t, const SwitchDrive& d, const HardwareFaults& f);
  SwitchState gatesAnew(double t, const SwitchDrive& d, const HardwareFaults& f);
  // Its last answer, and what gatesAnew read for it besides the relays: the lines in, the
  // weld fault and the fuse.
  SwitchState gates_;
  SwitchDrive gatesDrive_;
  bool gatesWelded_ = false, gatesBlown_ = false;
  bool gatesKept_ = false;     // the relays at rest since: gates_ stands for those

  const HardwareConfig& hw_;
  // Whether the FET pair passes discharge / charge current, [discharge gate on][charge
  // gate on]: fixed by the configuration, so tabulated once (fetPairConducts).
  bool passesDischarge_[2][2] = {}, passesCharge_[2][2] = {};
  RelayState relay_, precharge_;
  FuseState fuse_;
  double bus_V_ = 0.0;
  bool relayWelded_ = false;  // the weld fault as the last actuation saw it
};

}  // namespace packsim
