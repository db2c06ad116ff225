// Whether a scripted fault that needs the pack's current path ever had it. Three kinds
// act only through the switching hardware:
//   overcurrent          its extra current flows only while the main path is closed and
//                        conducts its direction (relay contact closed, fuse whole, FETs on)
//   charger_overvoltage  the charger's output reaches the pack only while the charger is
//                        on and connected, and its raised setpoint changes that output only
//                        once the pack's terminal voltage is above the charger's own setpoint
//                        (load.charger.voltage_V): below it the charger is current-limited
//                        (CC) with or without the fault, V = E + R·I_lim < V_set, and the
//                        current min(I_lim, (V_set - E)/R) is I_lim either way
//   welded_relay         a weld shows only when it holds a closed contact against an open
//                        command (the MCU's, or the monitor FAULT line's)
// A script can inject one where it cannot act -- a weld after a trip opened the relay, an
// over-current while the pack stands disconnected -- and the run then looks as if the BMS
// had nothing to do. FaultScheduler notes the path each tick an injection of these kinds is
// active, and an injection that never acted is a `fault_no_effect` event at the end of the
// run (noEffectText says why).
#pragma once
#include <string>

#include "core/scenario/faults_config.hpp"

namespace packsim {

// The switching hardware as the plant sees it over the next interval.
struct PathState {
  bool relayContactClosed = false;
  bool mainClosed = false;        // relay contact closed and fuse whole
  bool dischargeBlocked = false;  // a FET (or the fuse) blocks discharge current
  bool chargeBlocked = false;
  bool chargerOn = false;         // the charger is enabled (its current limit > 0)
  bool relayCommandedOpen = false;  // the coil drive is off (MCU pin or FAULT line)
  double terminal_V = 0.0;        // the pack's terminal voltage now
  double chargerSetpoint_V = 0.0; // the charger's own setpoint, without any fault (load.charger.voltage_V)
};

// What an injection saw while it was active.
struct EffectSeen {
  bool contactClosed = false;  // the relay contact was closed at some moment
  bool acted = false;          // its effect reached the plant at some moment
  // charger_overvoltage: the charger was on and connected at some moment, and the highest
  // terminal voltage then (against the charger's own setpoint, for the no-effect text)
  bool chargerReached = false;
  double peakTerminal_V = 0.0;
  double chargerSetpoint_V = 0.0;
};

// Whether this kind of injection needs the current path at all (the others always act).
bool needsCurrentPath(const FaultInjection& inj);
// Updates `seen` with one moment of the path while `inj` is active.
void noteEffect(const FaultInjection& inj, const PathState& p, EffectSeen& seen);
// Why an injection that never acted had no effect (the event's detail after its name).
std::string noEffectText(const FaultInjection& inj, const EffectSeen& seen);

}  // namespace packsim
