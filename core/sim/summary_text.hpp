// The run summary as the few lines a battery engineer reads first.
#pragma once
#include <string>

#include "core/scenario/scenario.hpp"
#include "core/sim/result.hpp"

namespace packsim {

std::string formatSummary(const Scenario& s, const RunResult& r);
// "cell N" (1-based over every cell), with its series group in a pack of parallel cells:
// "cell 74 (group 19)" in a 24s4p pack.
std::string cellName(int cell, int parallel);
// A duration as h:mm:ss, rounded to the second.
std::string clockText(double s);

}  // namespace packsim
