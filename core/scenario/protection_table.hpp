// The simulator's columns of the protection table. bms/bms_faults.hpp owns each
// protection (name, quantity, default threshold / hysteresis / delay in firmware units,
// severity, latch, what it opens); this table adds, per fault, what only the simulator
// needs: the SI unit of its YAML keys and the scale to firmware units, the range a
// scenario may set, what the firmware read and the event text. Everything else is
// derived: the YAML key is the fault's name, the SI defaults are the firmware defaults
// divided by the scale. The loader (load_bms.cpp), the bridge (bms_bridge.cpp
// makeBmsConfig) and the run tracker's fault events iterate it.
#pragma once
#include <array>
#include <bms/bms_faults.hpp>
#include <bms/bms_hal.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace packsim {

// One protection as a scenario sets it, in SI units (bms::ProtectionRule in firmware units).
struct ProtectionConfig {
  bool enabled = true;
  double threshold = 0.0;   // V, A or °C by protection (ProtectionSpec::unit)
  double hysteresis = 0.0;  // same unit
  double delay_s = 0.0;
  int opens = -1;           // bms::ActuatorBits it opens; -1 = the firmware table's default
  bms::FaultAction action = bms::FaultAction::Isolate;  // `action`: isolate | monitor | monitor_while_driving
};

// The scenario names of bms::FaultAction, in enum order.
const std::vector<std::string>& faultActionNames();

// Where a protection's YAML threshold goes.
enum class ThresholdUse : uint8_t {
  Rule,         // threshold_<unit> / hysteresis_<unit>, scaled into the firmware rule
  None,         // a rule on a condition: only enabled, delay_ms and opens
  WeldCurrent,  // threshold_<unit> scaled into bms::Config::weldCurrent_mA (the rule is a flag)
};

struct ProtectionSpec {
  bms::FaultId id;
  ThresholdUse use;
  const char* unit;  // SI unit of the threshold_ / hysteresis_ keys ("V", "A", "C"); "" for None
  double scale;      // firmware units per SI unit (V -> mV: 1e3, °C -> 0.1 °C: 10)
  double min, max;   // allowed threshold (SI)
  bool minOpen;      // min itself not allowed
  // What the firmware read, in firmware units, for the event text (nullptr: nothing shown).
  int32_t (*reading)(const bms::Telemetry&);
  // Event text. {value} and {threshold}: the reading and threshold in SI (3 decimals);
  // {value_fw} and {threshold_fw}: in firmware units; {count}: threshold + 1, the first
  // count that trips. " for <delay> ms" follows.
  const char* detail;
};

// The rows, indexed by bms::FaultId.
const std::array<ProtectionSpec, bms::kFaultCount>& protectionSpecs();
inline const ProtectionSpec& protectionSpec(bms::FaultId id) { return protectionSpecs()[static_cast<size_t>(id)]; }

// SI defaults from the firmware rows. The info and warning tiers (logged, opening
// nothing) are off until a scenario enables them; fatal protections are on.
ProtectionConfig defaultProtection(bms::FaultId id);
std::array<ProtectionConfig, bms::kFaultCount> defaultProtections();

// "max cell 4.251 V > 4.250 V for 500 ms": why a fault became active.
std::string protectionDetail(bms::FaultId id, int32_t threshold_fw, uint32_t delay_ms, const bms::Telemetry& tm);

}  // namespace packsim
