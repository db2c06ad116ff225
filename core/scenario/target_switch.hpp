// `--target cortex-m4` (packsim run / check): any scenario with packsim's core as ARM
// code on the virtual MCU, without editing it. The switch is the override
// `bms.firmware.target=<target>` (no elf: packsim's own core, the image host mode
// flashes; docs/firmware.md). A scenario whose firmware already runs on a target runs as
// it is. One that runs a user's library in host mode cannot: its target build is the
// user's own ELF (NotOnTarget). The loader refuses a pack of several monitor boards.
#pragma once
#include <stdexcept>
#include <string>

#include "core/scenario/overrides.hpp"

namespace packsim {

struct NotOnTarget : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// The scenario file with `overrides` and, when `target` is not empty, on that target.
Scenario loadScenarioOnTarget(const std::string& path, Overrides overrides, const std::string& target);

}  // namespace packsim
