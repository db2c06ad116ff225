// The monitor-IC driver table: every part packsim's core drives is one AfeDriver, in
// the device pattern of psfw_firmware and Zephyr (const config, API table, mutable
// data):
//
//   config  the part's settings as flashed: its own settings struct, carried in
//           Config::afe.settings (AfeSettings, opaque to the core; afeSettingsGet /
//           afeSettingsPut copy it), with the stack's shape in Config::afe and the
//           cell count and scaling in Config
//   api     AfeDriverApi: init, read-out, alert poll, fault clear, balancing, FETs,
//           a temperature input in 0.1 °C -- function pointers, each taking the whole
//           Config and the part's data
//   data    the part's driver state in RAM: its own struct, placed by its init in
//           MonitorDrivers::data (kAfeDataBytes, no heap)
//
// bms_monitor (the read-out, alert, clear, balance and FET calls) and bms_measure (the
// thermistor inputs) dispatch through the table of the part Config::afe.part names;
// nothing outside a part's own files (bms/afe/<part>_*) names a part. The registry is
// one line per part in bms/afe/monitor_parts.def, shared with the simulator's part
// descriptors (core/parts). How to write a part: docs/monitor-parts.md.
#pragma once
#include <cstdint>
#include <cstring>

#include "bms_afe.hpp"
#include "bms_config.hpp"
#include "bms_limits.hpp"
#include "packsim_fw.h"

namespace bms {

struct AfeDriverApi {
  // Places the part's state in `data` (zeroed RAM of kAfeDataBytes), takes its settings
  // and the stack's shape from c, addresses and configures every device. Returns true
  // when every device took its address and configuration. The core makes one full
  // read-out (readAll) right after it.
  bool (*init)(const Config& c, void* data, psfw_board* b, const psfw_board_api* api);
  // One read-out of every device: out[d] is written only where res[d] is Ok (a device
  // that fails keeps its last good reading); res[d] for d < c.afe.deviceCount.
  void (*readAll)(const Config& c, void* data, psfw_board* b, const psfw_board_api* api, DeviceReading* out,
                  FrameResult* res);
  // The protection flags alone (between read-outs): updates only io[d]'s fault, alert,
  // safetyA, safetyB (and fetStatus), only where res[d] is Ok.
  void (*pollAlerts)(const Config& c, void* data, psfw_board* b, const psfw_board_api* api, DeviceReading* io,
                     FrameResult* res);
  // Clears the devices' latched flags (a latch whose condition is still present stays).
  void (*clearFaults)(const Config& c, void* data, psfw_board* b, const psfw_board_api* api);
  // mask: one bit per series cell of the whole stack (kBalanceWords words, bottom
  // first); time_s: how long the devices keep the switches on.
  void (*writeBalance)(const Config& c, void* data, psfw_board* b, const psfw_board_api* api, const uint32_t* mask,
                       uint32_t time_s);
  // The part's own CHG / DSG FETs; nullptr: the part has none (the core then never
  // writes them).
  void (*writeFets)(const Config& c, void* data, psfw_board* b, const psfw_board_api* api, bool chargeOn,
                    bool dischargeOn);
  // Thermistor input i of a device's last good reading in 0.1 °C, kTempInvalid_dC for
  // a sensor at a rail (afeRatiometricTemp_dC for a part that reports divider codes).
  int16_t (*temperature_dC)(const Config& c, const DeviceReading& r, uint8_t input);
};

struct AfeDriver {
  const char* name;         // the part, as the scenario's hardware.afe.model spells it
  const AfeDriverApi* api;
  // Writes the part's firmware defaults into its settings block (the datasheet's
  // values; the simulator then sets what the scenario configures).
  void (*defaults)(AfeSettings& s);
};

// Each registered part's table, `afe_<name>` (bms/afe/<name>_afe.cpp).
#define MONITOR_PART(name) extern const AfeDriver afe_##name;
#include "afe/monitor_parts.def"
#undef MONITOR_PART

// The registry (bms/afe/monitor_parts.def, in its order; part 0 is the default).
// The table itself is read inline (the control tick looks its part up three times).
extern const AfeDriver* const kAfeDrivers[];
extern const uint8_t kAfeDriverCount;
inline uint8_t afeDriverCount() { return kAfeDriverCount; }
inline const AfeDriver* afeDriver(uint8_t part) {  // nullptr: no part under that index
  return part < kAfeDriverCount ? kAfeDrivers[part] : nullptr;
}
// Selects part `part` for the stack: Config::afe.part and the part's default settings.
// Returns false (c unchanged) for an index not registered.
bool afeSelect(Config& c, uint8_t part);

// A part's settings struct in and out of its block (trivially copyable, fits).
template <class T>
T afeSettingsGet(const AfeSettings& s) {
  static_assert(sizeof(T) <= kAfeSettingsBytes, "a part's settings exceed kAfeSettingsBytes");
  T t;
  std::memcpy(&t, s.bytes, sizeof t);
  return t;
}
template <class T>
void afeSettingsPut(AfeSettings& s, const T& t) {
  static_assert(sizeof(T) <= kAfeSettingsBytes, "a part's settings exceed kAfeSettingsBytes");
  std::memcpy(s.bytes, &t, sizeof t);
}

// For a part that reports ratiometric thermistor codes: the core's beta-model NTC on
// Config::scaling (bms_measure.hpp thermistorCodeToDeciCelsius).
int16_t afeRatiometricTemp_dC(const Config& c, const DeviceReading& r, uint8_t input);

// Devices the drivers address: Config::afe.deviceCount, at most kMaxDevices.
uint8_t afeDevices(const Config& c);

}  // namespace bms
