// `bms: {firmware: ...}`: which firmware runs on the simulated BMS microcontroller.
// Absent: packsim's own core (bms/). Present: a shared library built against the
// firmware contract (bms/packsim_fw.h), with its configuration blob (docs/firmware.md).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace packsim {

struct FirmwareSettings {
  bool library = false;             // a user firmware (a library, or an ELF on the target) runs instead of packsim's core
  std::string library_path;         // resolved when the scenario is loaded: the library, or the target's ELF
  std::string target;               // "" (host mode: a shared library) or "cortex-m4" (the ELF on the virtual MCU)
  double clock_hz = 168e6;          // target mode: the MCU's core clock (cycles -> time)
  std::vector<uint8_t> config;      // the blob handed to the firmware's init
  double watchdog_s = 1.0;          // CPU time one init or task call may take before it counts as hung
                                    // (target mode: the MCU's simulated time, a runaway past it)
  bool isTarget() const { return !target.empty(); }
};

}  // namespace packsim
