// The boundary between the BMS core and the hardware (or the simulator). Plain
// fixed-size structs: what a microcontroller reads from its monitor ICs and GPIO, and
// what it drives back. Nothing here points into simulator memory.
#pragma once
#include <cstdint>

#include "bms_faults.hpp"
#include "bms_limits.hpp"

namespace bms {

struct Inputs {
  uint32_t now_ms;                          // millisecond tick counter (wraps after 49 days)
  uint16_t cellCode[kMaxCells];             // raw monitor-IC cell ADC codes, index = series position
  uint16_t thermistorCode[kMaxThermistors]; // raw ratiometric thermistor ADC codes
  int32_t currentCode;                      // current-sense ADC code (signed converter)
  bool eStopPulled;                         // any E-switch input asserted (GPIO)
  bool runRequest;                          // key / drive-enable input
  bool resetRequest;                        // operator reset of latched faults
};

enum class State : uint8_t { Init = 0, Standby, Normal, Error };

struct Telemetry {
  uint16_t cellVoltage_mV[kMaxCells];
  int16_t temperature_dC[kMaxThermistors];
  int32_t packCurrent_mA;
  uint16_t minCell_mV;
  uint16_t maxCell_mV;
  int16_t maxTemp_dC;
};

struct Outputs {
  bool relayClose;          // normally-open main relay: true = energise (close)
  bool dischargeFetOn;
  bool chargeFetOn;
  State state;
  uint32_t faultActive;     // bit per FaultId: condition present and debounced
  uint32_t faultLatched;    // bit per FaultId: latched until operator reset
  Telemetry telemetry;
};

}  // namespace bms
