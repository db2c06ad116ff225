// BMS core configuration: what the firmware is flashed with. Firmware units only
// (mV, mA, deci-degC, ms); the simulator converts the scenario's SI values once.
#pragma once
#include <cstdint>

#include "bms_faults.hpp"
#include "bms_limits.hpp"

namespace bms {

// What a protection rule compares. The core computes each quantity once per tick.
enum class Quantity : uint8_t {
  MaxCell_mV = 0,
  MinCell_mV,
  DischargeCurrent_mA,  // +I (positive current discharges)
  ChargeCurrent_mA,     // -I
  MaxTemp_dC,
  Count
};
constexpr uint8_t kQuantityCount = static_cast<uint8_t>(Quantity::Count);

// One row of the protection table. A fault becomes active when `quantity` is beyond
// `threshold` (above or below, by `tripAbove`) continuously for `delay_ms`; a
// non-latching fault clears once the quantity is back by `hysteresis`.
struct ProtectionRule {
  FaultId id;
  Quantity quantity;
  bool tripAbove;
  int32_t threshold;
  int32_t hysteresis;
  uint32_t delay_ms;
  Severity severity;
  bool latch;
  uint8_t opens;  // ActuatorBits
  bool enabled;
};

// Conversion from monitor-IC codes to firmware units (the nominal datasheet values:
// the firmware does not know the simulated part's gain error).
struct SensorScaling {
  float cellLsb_uV;            // cell voltage per ADC code
  float currentZeroCode;       // current-sense ADC code at 0 A
  float currentLsb_mA;         // mA per current-sense ADC code
  float thermFullScaleCode;    // ADC code at the reference (ratio 1.0)
  float thermPullup_ohm;       // divider: reference - pullup - NTC - ground
  float thermR25_ohm;
  float thermBeta_K;
};

struct Config {
  uint16_t cellCount;
  uint8_t thermistorCount;
  uint32_t tickPeriod_ms;
  SensorScaling scaling;
  ProtectionRule rules[kFaultCount];
};

// Defaults for a LiPo/NMC pack; callers overwrite thresholds from the scenario.
Config defaultConfig(uint16_t cellCount, uint8_t thermistorCount);

}  // namespace bms
