// Acquisition: runs the monitor-IC driver on every reply, keeps each device's last
// good reading and its consecutive-bad-reply count, converts codes into firmware
// units (mV, mA, deci-degC) and derives the per-tick quantities the protection table
// compares. A device that has never answered contributes no cell values (the
// comm-loss rule catches it); a device that stops answering keeps its last values
// until the comm-loss rule trips.
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
  DeviceReading device[kMaxDevices];
  bool seen[kMaxDevices];      // at least one good reply so far
  uint8_t bad[kMaxDevices];    // consecutive bad replies (saturates at 255)
  bool freshFault[kMaxDevices];  // this tick's good reply reported the device's own fault
};

void acquisitionReset(AcquisitionState& a);
// True once every device has answered at least once.
bool acquisitionComplete(const Config& cfg, const AcquisitionState& a);

// Parses this tick's replies, fills telemetry (voltages, temperatures, current, bus,
// comm status, min/max) and the measurement quantities of the protection table.
void measure(const Config& cfg, const Inputs& in, AcquisitionState& a, Telemetry& tm,
             int32_t quantity[kQuantityCount]);

}  // namespace bms
