#include "core/sim/fault_effect.hpp"

#include <algorithm>

#include "core/text_fmt.hpp"

namespace packsim {

bool needsCurrentPath(const FaultInjection& inj) {
  return inj.kind == FaultKind::Overcurrent || inj.kind == FaultKind::ChargerOvervoltage ||
         inj.kind == FaultKind::WeldedRelay;
}

void noteEffect(const FaultInjection& inj, const PathState& p, EffectSeen& seen) {
  seen.contactClosed = seen.contactClosed || p.relayContactClosed;
  switch (inj.kind) {
    case FaultKind::Overcurrent:  // extra discharge current (> 0) or charge current (< 0)
      seen.acted = seen.acted || (p.mainClosed && !(inj.value >= 0.0 ? p.dischargeBlocked : p.chargeBlocked));
      break;
    case FaultKind::ChargerOvervoltage:
      if (p.mainClosed && p.chargerOn && !p.chargeBlocked) {
        seen.peakTerminal_V = seen.chargerReached ? std::max(seen.peakTerminal_V, p.terminal_V) : p.terminal_V;
        seen.chargerReached = true;
        seen.chargerSetpoint_V = p.chargerSetpoint_V;
        // Above its own setpoint a sound charger would cut the current; below it the
        // charger is current-limited either way (fault_effect.hpp).
        seen.acted = seen.acted || p.terminal_V > p.chargerSetpoint_V;
      }
      break;
    case FaultKind::WeldedRelay:
      seen.acted = seen.acted || (p.relayContactClosed && p.relayCommandedOpen);
      break;
    default: seen.acted = true;
  }
}

std::string noEffectText(const FaultInjection& inj, const EffectSeen& seen) {
  switch (inj.kind) {
    case FaultKind::Overcurrent:
      return seen.contactClosed
                 ? std::string("no extra current flowed: the FETs (or a blown fuse) blocked its direction the whole time")
                 : std::string("no extra current flowed: the relay contact was open (or the fuse blown) the whole time");
    case FaultKind::ChargerOvervoltage:
      if (seen.chargerReached)
        return fmt("the charger stayed current-limited (CC) the whole time: the pack's terminal voltage peaked at "
                   "%.3f V, below the charger's own setpoint of %.3f V, so a raised setpoint changed nothing",
                   seen.peakTerminal_V, seen.chargerSetpoint_V);
      return "the charger's output never reached the pack: the charger was off, or the main path open or "
             "blocked, the whole time";
    case FaultKind::WeldedRelay:
      return seen.contactClosed
                 ? std::string("the relay was never commanded open while welded, so the weld never held it: the "
                               "BMS's weld detection was not put to the test")
                 : std::string("the relay contact was open the whole time: a weld holds a closed contact, and the "
                               "relay never closed while welded");
    default: return "";
  }
}

}  // namespace packsim
