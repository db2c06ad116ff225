// The BMS control core: one pure step per tick over fixed-size structs.
//
//   step(cfg, state, in, out):
//     1. measure: codes -> mV / mA / deci-degC, min/max quantities
//     2. protections: debounce every rule of the table, latch fatal ones
//     3. state machine: one function per state decides the next state
//     4. actuators: relay and FET commands follow the state and the fault table
//
// No heap, no exceptions, no I/O, no globals: the same sources run on the
// microcontroller and in the simulator. Commands take effect from the next tick.
#pragma once
#include <cstdint>

#include "bms_config.hpp"
#include "bms_hal.hpp"
#include "bms_protect.hpp"

namespace bms {

struct CoreState {
  State state;
  uint32_t stateEntered_ms;
  bool firstTick;
  ProtectionState protection;
  int32_t quantity[kQuantityCount];
};

void init(CoreState& s);
void step(const Config& cfg, CoreState& s, const Inputs& in, Outputs& out);

const char* stateName(State st);

}  // namespace bms
