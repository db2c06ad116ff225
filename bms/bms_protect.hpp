// The protection table evaluated once per tick: per rule, a time-based debounce
// (the condition must hold for delay_ms), hysteresis on recovery, and latching.
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
void protectionUpdate(const Config& cfg, const int32_t quantity[kQuantityCount], uint32_t now_ms,
                      ProtectionState& ps);
// Faults (active or latched) of Fatal severity.
uint32_t fatalFaults(const Config& cfg, const ProtectionState& ps);
// Actuators that active or latched faults keep open (ActuatorBits).
uint8_t openedActuators(const Config& cfg, const ProtectionState& ps);
// Operator reset: drops latches whose condition has cleared.
void clearLatched(ProtectionState& ps);

}  // namespace bms
