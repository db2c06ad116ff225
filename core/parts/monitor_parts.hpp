// The simulator's part registry: one MonitorPart per monitor IC, registered by its line
// in bms/afe/monitor_parts.def (which also registers its firmware driver). A part is
// its own files -- the register-level model (models/afe/<part>.*), the firmware driver
// and its table entry (bms/afe/<part>_*), this descriptor (core/parts/<part>_part.cpp)
// -- and nothing else names it: the loader (load_hardware.cpp), the firmware image
// builder (bms_bridge.cpp) and the chain path (monitor_chain_path.cpp) iterate the
// registry. How to add one: docs/monitor-parts.md.
#pragma once
#include <bms/bms_afe_driver.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "models/afe/monitor_config.hpp"
#include "models/afe/monitor_part.hpp"
#include "models/sensors/adc.hpp"

namespace packsim {

class YamlMap;

// A key of hardware.afe that only some parts have; `hint` is added to the error a part
// without it gives ("" for none).
struct PartKey {
  const char* key;
  const char* hint;
};

struct MonitorPart {
  const char* name;     // hardware.afe.model
  int max_cells;        // cells per device
  int max_thermistors;  // thermistor inputs per device
  bool stacked;         // devices share one bus (several per board: devices_per_board)
  // Non-null: the part reports cells in a unit of its own, so hardware.cell_adc may
  // not set lsb_uV or bits; the reason, e.g. "reports cells in mV".
  const char* fixed_cell_codes;
  // The part's defaults: its cell ADC channel (LSB, full scale, noise) and its link,
  // conversion and measurement timing, thermistor inputs.
  void (*defaults)(MonitorConfig& a, AdcChannel& cell_adc);
  std::vector<PartKey> keys;  // its own keys of hardware.afe (read by read_keys)
  // Reads the part's own keys of hardware.afe (after the common ones), in its ranges.
  void (*read_keys)(YamlMap& afe, MonitorConfig& a);
  // Whether the part balances on its own as configured (needs hardware.balancing).
  bool (*balances_on_its_own)(const MonitorConfig& a);
  // Its register-level model (models/afe).
  std::unique_ptr<MonitorChain> (*make_chain)(const MonitorConfig& a, int cellCount, uint64_t seed);
  // Its firmware driver, and the scenario's settings in the driver's units: called on
  // the driver's defaults (bms::afeSelect), sets what the scenario configures.
  const bms::AfeDriver* driver;
  void (*firmware_settings)(const MonitorConfig& a, bms::AfeSettings& s);
};

// Every registered part, in registry order (the first is the default).
const std::vector<const MonitorPart*>& monitorParts();
// The part of that name (hardware.afe.model); std::invalid_argument naming the
// registered parts when there is none.
const MonitorPart& monitorPart(const std::string& name);
// The part's index in the firmware's driver registry (bms::AfeConfig::part).
uint8_t firmwarePartIndex(const MonitorPart& p);

}  // namespace packsim
