// Scripted fault injections (`faults:` in a scenario). Each starts at a time (`at_s`)
// or when a condition on the plant's truth first holds (`when: "cell_min_V < 3.3"`),
// and lasts `duration_s` or for the rest of the run. Indices are 0-based here; the
// YAML counts cells (1..series*parallel), series groups (1..series), devices and
// thermistors from 1.
#pragma once
#include <string>
#include <vector>

namespace packsim {

enum class FaultKind {
  Overcurrent,        // extra load current (A)
  HotCell,            // heat source in one cell (W)
  InternalShort,      // resistance across one cell (Ω)
  EStop,              // E-switch pulled (internal or external)
  DeviceSilent,       // monitor IC gives no reply
  CrcErrors,          // monitor IC replies corrupted at a rate
  DeviceStuck,        // monitor IC replies only 0x00 or only 0xFF
  BrokenLink,         // every device above one goes silent
  ChannelGain,        // cell input gain error
  ChannelOffset,      // cell input offset (V)
  ThermistorOpen,
  ThermistorShort,
  WeldedRelay,
  CurrentSensorDrift, // current-sense offset (A), optionally growing (A/h) from the start
  ChargerOvervoltage, // charger output above its setpoint (V)
  HostDead,           // the MCU hangs: no more BMS ticks, its outputs hold their last level
  ResetRequest,       // operator reset GPIO asserted (one BMS tick unless duration_s)
  KeyOff,             // the run request (key / drive enable) released: the race is over
  SupplyBrownout,     // the BMS board's 12 V rail dips (V); below the MCU's brown-out threshold it is held in reset
};

const char* faultKindName(FaultKind k);

enum class Quantity { Time_s, CellMin_V, CellMax_V, SocMin, SocMax, SocMean, PackCurrent_A, PackVoltage_V, TempMax_C };

struct Condition {
  Quantity quantity = Quantity::Time_s;
  bool greater = true;   // > / >=   versus  < / <=
  bool inclusive = false;
  double value = 0.0;
  std::string text;      // as written, for events
  bool holds(double x) const {
    return greater ? (inclusive ? x >= value : x > value) : (inclusive ? x <= value : x < value);
  }
};

struct FaultInjection {
  FaultKind kind = FaultKind::Overcurrent;
  bool hasCondition = false;
  double at_s = 0.0;
  Condition when;
  double duration_s = 0.0;  // 0: permanent
  int index = 0;            // cell (0..S*P-1), series group (channel faults), device or thermistor (0-based), by kind
  int parallel = 1;         // cells per series group, to name a cell's group
  double value = 0.0;       // A, W, Ω, rate, gain, V … by kind
  double rate_per_s = 0.0;  // current_sensor_drift: offset growth (A/s) from the start
  bool external = false;    // E-switch: which one
  int line = 0;             // where it was written (for reports)
  std::string origin;       // set when an override (or a Python dict) wrote it: "faults[1], set by an override"
  std::string where() const { return origin.empty() ? "line " + std::to_string(line) : origin; }
  std::string describe() const;
  // Its fault_injected event's detail: describe(), and a `when:` injection's condition
  // after it (its fault_removed event's detail is describe() alone).
  std::string injectedDetail() const;
  std::string cellText() const;  // "cell 74 (group 19)"; "cell 5" without parallel cells
};

// Whether a fault_injected event's detail is that of an injection described as
// `described` (FaultInjection::describe(): with or without a `when:` condition after it).
bool injectionDetailIs(const std::string& injectedDetail, const std::string& described);

}  // namespace packsim
