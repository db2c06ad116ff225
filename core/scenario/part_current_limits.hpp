// A monitor part with current protections of its own (the BQ76952: OCC, OCD1, SCD across
// its shunt) acts before the BMS wherever its threshold, in amps on the scenario's shunt,
// lies below the BMS's over-current limit or the load's peak: the pack trips on the part's
// FAULT line ("monitor IC protection latched") at a current the scenario never names. The
// part's data-sheet defaults (OCD1 8 mV: 1.6 A on a 5 mOhm shunt) do so on ordinary loads.
// Each such threshold is a load-time warning naming the key, its amps and what it undercuts.
#pragma once
#include <yaml-cpp/yaml.h>

#include "core/scenario/scenario.hpp"

namespace packsim {

// `root`: the merged scenario tree (to tell a stated threshold from the part's default).
void warnPartCurrentLimits(const YAML::Node& root, const Scenario& s);

}  // namespace packsim
