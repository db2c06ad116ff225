// Acquisition: the core's record of its monitor ICs. The read-out task hands it each
// read-out's (or alert poll's) result per device: the drivers (bms_monitor.hpp) have
// already written every good reading into `device`, so a device keeps its last good
// reading; `bad` counts consecutive bad reads of it. Every control tick, measure()
// converts the held readings and the MCU's own inputs into firmware units (mV, mA,
// deci-degC) and derives the quantities the protection table compares. A device that
// has never answered a full read-out contributes no cell values (the comm-loss rule
// catches it); one that stops answering keeps its last values until that rule trips.
#pragma once
#include <cstdint>

#include "bms_afe.hpp"
#include "bms_config.hpp"
#include "bms_hal.hpp"

namespace bms {

uint16_t cellCodeToMillivolts(const SensorScaling& s, uint16_t code);
int32_t currentCodeToMilliamps(const SensorScaling& s, int32_t code);
// NTC beta model on a ratiometric divider. Codes at either rail (open or short
// sensor) return kTempInvalid_dC instead of a temperature.
int16_t thermistorCodeToDeciCelsius(const SensorScaling& s, uint16_t code);
constexpr int16_t kTempInvalid_dC = INT16_MIN;

struct AcquisitionState {
  DeviceReading device[kMaxDevices];  // last good reading of each device (drivers write here)
  bool seen[kMaxDevices];             // at least one good full read-out so far
  uint8_t bad[kMaxDevices];           // consecutive bad reads (saturates at 255)
  FrameResult last[kMaxDevices];      // how the last read of each device ended
  // Bit d: device d has delivered cells measured since the estimators last took a
  // reading (a good full read-out that is not its part's previous loop again).
  uint64_t newCells;
  // Every device's cells are new since the estimators last took a reading, and some of
  // them arrived since the last control tick (the core takes it and clears it).
  bool fresh;
  // A full read-out ran since the last control tick, whatever it brought (the core
  // clears it with fresh): an alert poll due in the same tick has nothing to add.
  bool readOut;
};

void acquisitionReset(AcquisitionState& a);
// True once every device has answered at least one full read-out. (Inline: asked at
// every control tick.)
inline bool acquisitionComplete(const Config& cfg, const AcquisitionState& a) {
  for (uint8_t d = 0; d < cfg.afe.deviceCount; ++d)
    if (!a.seen[d]) return false;
  return true;
}

// The results of one read of the stack: a full read-out (cells, temperatures, flags;
// full = true) or an alert poll (flags only). The drivers wrote the good readings into
// a.device already; this counts good and bad reads per device and marks the reading
// fresh once every device has new cells: a device that failed, or whose part's loop had
// not run again, holds a reading the estimators have used already.
void acquireResults(const Config& cfg, AcquisitionState& a, const FrameResult* result, bool full);

// The current the devices' cells were measured under, where their part measures both in
// one loop of its own (DeviceReading::loopCurrent on every device; their mean, rounded
// toward zero): true and `mA` set. False where the cells were read on the host's command
// (the MCU's current of the tick is theirs) or a device's loop current is not known.
bool loopCurrent(const Config& cfg, const AcquisitionState& a, int32_t& mA);

// One control tick: the held readings plus the MCU's own inputs (current, bus voltage,
// MCU thermistors, GPIO) into telemetry (voltages, temperatures, current, bus, comm
// status, min/max) and the measurement quantities of the protection table.
// A ratiometric part's thermistor input whose code has not changed since this tick's
// Telemetry converted it keeps that temperature (DeviceReading::thermConverted): call it
// with the same Telemetry every tick (the firmware's Outputs), or with readings built
// afresh. Returns whether any of temperature_dC[0 .. thermistorCount) now reads
// differently from what tm held before the call.
bool measure(const Config& cfg, const Inputs& in, AcquisitionState& a, Telemetry& tm,
             int32_t quantity[kQuantityCount]);

}  // namespace bms
