// A rest threshold the current sensor's noise crosses: packsim's core counts |I| below
// bms.soc.rest_current_A (for re-anchoring its SOC on the OCV) or bms.balancing.rest_
// current_A (for balancing at rest) as rest, and one reading at or above it restarts the
// rest time. With Gaussian noise of sigma on the reading at rest, a reading passes the
// threshold T with probability erfc(T / (sigma sqrt 2)) each BMS tick, so every tick_s /
// that on average. When that is under ten times the rest time (a rest completes less than
// about nine times in ten), the run's rests -- and what waits for them -- come late, and a
// user is told at load time with the numbers (docs/scenario.md, "Warnings").
#pragma once
#include <string>
#include <vector>

#include "core/scenario/scenario.hpp"

namespace packsim {

class Provenance;

void checkRestNoise(const Scenario& s, const Provenance& p, std::vector<std::string>& out);

// The mean time between two readings at or above threshold_A in magnitude, for readings
// every tick_s with Gaussian noise of noise_A_rms around 0 A (infinity without noise).
double meanTimeBetweenNoiseBreaks_s(double threshold_A, double noise_A_rms, double tick_s);

}  // namespace packsim
