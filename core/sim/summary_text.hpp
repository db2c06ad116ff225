// The run summary as the few lines a battery engineer reads first.
#pragma once
#include <string>

#include "core/scenario/scenario.hpp"
#include "core/sim/result.hpp"

namespace packsim {

std::string formatSummary(const Scenario& s, const RunResult& r);
// A duration as h:mm:ss, rounded to the second.
std::string clockText(double s);

}  // namespace packsim
