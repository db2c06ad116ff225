// Fault identifiers, severities and the actuators a fault acts on.
#pragma once
#include <cstdint>

namespace bms {

// The first five keep their historical bit positions (result files, scenarios).
enum class FaultId : uint8_t {
  CellOverVoltage = 0,
  CellUnderVoltage,
  OverCurrentDischarge,
  OverCurrentCharge,
  OverTemperature,            // discharge over-temperature (the historical "overtemperature")
  OverTemperatureCharge,      // hot cells may not be charged
  UnderTemperatureDischarge,
  UnderTemperatureCharge,
  BoardOverTemperature,       // monitor IC die / board
  CommLoss,                   // N consecutive bad monitor replies
  PlausibilityCellSum,        // sum of cells vs module/stack channel
  ThermistorFault,            // a thermistor reads at a rail (open or short)
  CurrentSensorFault,         // current-sense code at a rail
  EStop,                      // an E-switch is pulled
  MonitorFault,               // the monitor IC's own protection latched (FAULT line)
  RelayWelded,                // current still flows after the relay was commanded open
  PrechargeFailed,            // precharge timed out on every attempt
  TemperatureWarning,         // recommended safety limit (cell health), no action
  CellImbalance,              // operating limit: max - min cell spread, no action
  Count
};
constexpr uint8_t kFaultCount = static_cast<uint8_t>(FaultId::Count);

// Three tiers as in foxBMS: operating limit (info), recommended safety limit (warning),
// maximum safety limit (fatal: isolates the pack and latches).
enum class Severity : uint8_t { Info = 0, Warning = 1, Fatal = 2 };

// Bit masks of the actuators a fault opens.
enum ActuatorBits : uint8_t {
  kActRelay = 1u << 0,
  kActDischargeFet = 1u << 1,
  kActChargeFet = 1u << 2,
  kActAll = kActRelay | kActDischargeFet | kActChargeFet,
};

constexpr uint32_t faultBit(FaultId id) { return 1u << static_cast<uint8_t>(id); }

// Short stable name for logs and the events table ("cell_overvoltage", ...).
const char* faultName(FaultId id);

}  // namespace bms
