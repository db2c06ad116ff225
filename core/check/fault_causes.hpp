// Which BMS faults a scripted injection can cause (packsim check attributes each
// detection to the injection that caused it, not to whatever fault comes next).
#pragma once
#include <string>
#include <vector>

#include "core/scenario/faults_config.hpp"

namespace packsim {

// The protection rows (bms::faultName) an injection of this kind can raise, directly or
// through what it does to the pack; empty for operator inputs (reset_request, key_off).
const std::vector<std::string>& faultsCausedBy(FaultKind kind);
// The kind named by a fault_injected event's detail (its first word); false if none.
bool faultKindOfDetail(const std::string& detail, FaultKind& kind);

}  // namespace packsim
