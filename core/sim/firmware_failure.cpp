#include "core/sim/firmware_failure.hpp"

#include <cstdio>

namespace packsim {

std::string firmwareFailure(const Scenario& s, const RunResult& r) {
  for (const Event& e : r.events) {
    if (e.kind != "firmware_fault") continue;
    char at[48];
    std::snprintf(at, sizeof at, " failed at %.3f s: ", e.time_s);
    const std::string cause = e.detail.substr(0, e.detail.find("; the MCU is stopped"));
    const std::string who = s.bms.firmware.library ? (s.bms.firmware.isTarget() ? "the firmware ELF '" : "the firmware library '") + s.bms.firmware.library_path + "'"
                                   : s.bms.firmware.isTarget() ? "packsim's core firmware '" + s.bms.firmware.library_path + "'"
                                                               : std::string("packsim's core firmware");
    return who + at + cause;
  }
  return "";
}

}  // namespace packsim
