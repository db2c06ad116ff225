#include "core/scenario/target_switch.hpp"

namespace packsim {

Scenario loadScenarioOnTarget(const std::string& path, Overrides overrides, const std::string& target) {
  Scenario s = loadScenarioFileWithOverrides(path, overrides);
  if (target.empty() || s.bms.firmware.isTarget()) return s;
  if (s.bms.firmware.library)
    throw NotOnTarget(path + ": runs the firmware library '" + s.bms.firmware.library_path +
                      "' in host mode; --target " + target +
                      " runs packsim's core on the target, and a library's target build is its own ELF "
                      "(bms.firmware: {target: " + target + ", elf: ...}, as scenarios/firmware/target/ does)");
  overrides.emplace_back("bms.firmware.target", target);
  return loadScenarioFileWithOverrides(path, overrides);
}

}  // namespace packsim
