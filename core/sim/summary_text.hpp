// The run summary as the few lines a battery engineer reads first.
#pragma once
#include <string>

#include "core/scenario/scenario.hpp"
#include "core/sim/result.hpp"

namespace packsim {

std::string formatSummary(const Scenario& s, const RunResult& r);

}  // namespace packsim
