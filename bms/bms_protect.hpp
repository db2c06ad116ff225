// The protection table evaluated once per tick: per rule, a time-based debounce
// (the condition must hold for delay_ms), hysteresis on recovery, and latching. What a
// fatal fault does depends on its action (bms_faults.hpp FaultAction) and on whether
// the pack is driving: `driving` is true while the core is in state Normal.
#pragma once
#include <cstdint>

#include "bms_config.hpp"

namespace bms {

struct ProtectionState {
  uint32_t violatingSince_ms[kFaultCount];
  uint32_t violating;  // bit per fault: condition beyond threshold at the last tick
  uint32_t active;     // bit per fault: debounced
  uint32_t latched;    // bit per fault: stays set until clearLatched()
};

void protectionReset(ProtectionState& ps);
void protectionUpdate(const Config& cfg, const int32_t quantity[kQuantityCount], uint32_t now_ms, bool driving,
                      ProtectionState& ps);
// Rules that isolate now: Fatal severity with action Isolate, or MonitorWhileDriving
// while not driving.
uint32_t isolatingRules(const Config& cfg, bool driving);
// The rules of the faults present (active or latched) only, out of line: what the two
// below answer when a fault is present.
uint32_t fatalFaultsOfPresent(const Config& cfg, const ProtectionState& ps, bool driving);
uint8_t openedActuatorsOfPresent(const Config& cfg, const ProtectionState& ps, bool driving);
// Faults (active or latched) that isolate now. Inline where none is present, the usual
// tick (the core asks three times a tick).
inline uint32_t fatalFaults(const Config& cfg, const ProtectionState& ps, bool driving) {
  return (ps.active | ps.latched) == 0 ? 0u : fatalFaultsOfPresent(cfg, ps, driving);
}
// Actuators that the isolating faults keep open (ActuatorBits); inline as fatalFaults.
inline uint8_t openedActuators(const Config& cfg, const ProtectionState& ps, bool driving) {
  return (ps.active | ps.latched) == 0 ? uint8_t{0} : openedActuatorsOfPresent(cfg, ps, driving);
}
// Operator reset: drops latches whose condition has cleared.
void clearLatched(ProtectionState& ps);

}  // namespace bms
