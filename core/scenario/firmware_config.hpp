// `bms: {firmware: ...}`: which firmware runs on the simulated BMS microcontroller.
// Absent: packsim's own core (bms/). Present: a shared library built against the
// firmware contract (bms/packsim_fw.h), with its configuration blob (docs/firmware.md).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace packsim {

struct FirmwareSettings {
  bool library = false;             // a user firmware library runs instead of packsim's core
  std::string library_path;         // resolved when the scenario is loaded
  std::vector<uint8_t> config;      // the blob handed to the firmware's init
  double watchdog_s = 1.0;          // CPU time one init or task call may take before it counts as hung
};

}  // namespace packsim
