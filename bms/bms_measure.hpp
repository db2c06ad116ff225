// Converts raw monitor-IC codes into firmware units (mV, mA, deci-degC) and derives
// the per-tick quantities the protection table compares.
#pragma once
#include <cstdint>

#include "bms_config.hpp"
#include "bms_hal.hpp"

namespace bms {

uint16_t cellCodeToMillivolts(const SensorScaling& s, uint16_t code);
int32_t currentCodeToMilliamps(const SensorScaling& s, int32_t code);
// NTC beta model on a ratiometric divider. Codes at either rail (open or short
// sensor) return kTempInvalid_dC instead of a temperature.
int16_t thermistorCodeToDeciCelsius(const SensorScaling& s, uint16_t code);
constexpr int16_t kTempInvalid_dC = INT16_MIN;

// Fills telemetry (voltages, temperatures, current, min/max) from the inputs and
// the protection quantities from the telemetry.
void measure(const Config& cfg, const Inputs& in, Telemetry& tm, int32_t quantity[kQuantityCount]);

}  // namespace bms
