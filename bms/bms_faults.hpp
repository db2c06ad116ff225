// The protection table: one row per fault, the only place a protection is defined.
// A row names the fault (the string the events, the scenario key and the result files
// use), what it compares, its default threshold / hysteresis / delay in firmware
// units, its severity, whether it latches and what it opens; indexed by FaultId, checked
// at compile time (bms_faults.cpp). The simulator derives its columns (YAML key, SI unit
// and scale, range, event text) from these rows: core/scenario/protection_table.hpp.
//
// Adding a protection: one FaultId below and its row in bms_faults.cpp (same position),
// then its simulator row in core/scenario/protection_table.cpp.
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
  FetOverTemperature,         // a thermistor on the power FETs
  Count
};
constexpr uint8_t kFaultCount = static_cast<uint8_t>(FaultId::Count);
static_assert(kFaultCount <= 32, "fault bits are one uint32_t");

// Three tiers as in foxBMS: operating limit (info), recommended safety limit (warning),
// maximum safety limit (fatal: isolates the pack and latches).
enum class Severity : uint8_t { Info = 0, Warning = 1, Fatal = 2 };

// What a fatal fault does, chosen per protection in the firmware configuration:
//   Isolate              open what the row opens and latch (the default)
//   Monitor              log and warn only: the fault is reported active, opens nothing,
//                        never latches
//   MonitorWhileDriving  Monitor while the pack drives (state Normal: no real-time
//                        isolation on track), Isolate in every other state (off track:
//                        standing, precharging, charging). A fault still present when
//                        driving ends isolates then.
enum class FaultAction : uint8_t { Isolate = 0, Monitor = 1, MonitorWhileDriving = 2 };

// Bit masks of the actuators a fault opens.
enum ActuatorBits : uint8_t {
  kActRelay = 1u << 0,
  kActDischargeFet = 1u << 1,
  kActChargeFet = 1u << 2,
  kActAll = kActRelay | kActDischargeFet | kActChargeFet,
};

// What a protection rule compares. The core computes each quantity once per tick.
enum class Quantity : uint8_t {
  MaxCell_mV = 0,
  MinCell_mV,
  DischargeCurrent_mA,  // +I (positive current discharges)
  ChargeCurrent_mA,     // -I
  MaxTemp_dC,
  MaxTempCharging_dC,   // max temperature while the charger is connected, else "cold"
  MinTemp_dC,
  MinTempCharging_dC,   // min temperature while the charger is connected, else "warm"
  MaxDie_dC,            // hottest monitor IC die
  CommBadFrames,        // worst consecutive-bad-reply count over the devices
  CellSumError_mV,      // worst |stack channel - sum of cells| per cell, over devices
  InvalidThermistors,   // thermistor channels at a rail
  CurrentCodeAtRail,    // 1 while the current-sense code sits at either rail
  EStopPulled,          // 1 while an E-switch is pulled
  MonitorFaultLine,     // 1 while a monitor IC reports its own latched fault
  RelayStuckClosed,     // 1 while the relay, commanded open for the settle time, still
                        // carries current or its auxiliary contact still reads closed
  PrechargeFailed,      // 1 once every precharge attempt timed out
  CellSpread_mV,        // max - min cell
  MaxFet_dC,            // hottest FET thermistor (Config::therm)
  Count
};
constexpr uint8_t kQuantityCount = static_cast<uint8_t>(Quantity::Count);

// The firmware unit of a row's threshold and hysteresis. Flag: a condition (0/1 or a
// count of bad channels) that trips as soon as it is present; the threshold is not a
// setting. Replies: a count of consecutive bad monitor replies.
enum class FaultUnit : uint8_t { Flag = 0, Replies, mV, mA, dC };

// One protection. A fault becomes active when `quantity` is beyond `threshold` (above
// or below, by `tripAbove`) continuously for `delay_ms`; a non-latching fault clears
// once the quantity is back by `hysteresis`.
struct FaultRow {
  FaultId id;
  const char* name;  // snake_case: events, `bms.protections.<name>`, HDF5 /bms fault_bits
  Quantity quantity;
  bool tripAbove;
  int32_t threshold;   // default, in `unit`
  int32_t hysteresis;  // default, in `unit`
  uint32_t delay_ms;   // default debounce
  FaultUnit unit;
  Severity severity;
  bool latch;
  uint8_t opens;  // ActuatorBits
};

// The row of a fault (bms_faults.cpp holds the table, checked at compile time).
const FaultRow& faultRow(FaultId id);

constexpr uint32_t faultBit(FaultId id) { return 1u << static_cast<uint8_t>(id); }

// Short stable name for logs and the events table ("cell_overvoltage", ...).
const char* faultName(FaultId id);

}  // namespace bms
