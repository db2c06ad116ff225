// Hardware a scenario does not state, derived from what it does state instead of
// being copied from a reference system (docs/scenario.md "Defaults"):
//  - bms.protections.overcurrent_charge.threshold_A: the cell's max_charge_C (else 1C)
//    x capacity x parallel cells;
//  - bms.protections.overcurrent_discharge.threshold_A: the cell's max_discharge_C x
//    capacity x parallel when the cell states one (else the firmware table's value,
//    with a warning that it is not the pack's);
//  - hardware.current_sense.amp_gain (when neither shunt_ohm nor amp_gain is stated): a
//    range of kSensorRangeOverLimit x the highest enabled over-current limit, and at
//    least kSensorRangeOverLoad x the load's peak current.
// Each derived value is recorded with its reason (core/scenario/provenance.hpp) and
// reported as a warning.
#pragma once
#include <yaml-cpp/yaml.h>

#include "core/scenario/scenario.hpp"

namespace packsim {

constexpr double kDefaultChargeC = 1.0;          // charge limit of a cell that states no max_charge_C
constexpr double kSensorRangeOverLimit = 1.5;    // sensor full scale over the highest over-current limit
constexpr double kSensorRangeOverLoad = 1.25;    // ... and over the load's peak current

// The largest discharge (> 0) and charge (> 0, as a magnitude) current the load asks
// for: a power load at the pack's lowest voltage (series x v_min_V); a charger's current_A.
double loadPeakDischarge_A(const Scenario& s);
double loadPeakCharge_A(const Scenario& s);

// `root`: the merged scenario tree (what is stated). Called by the loader after every
// section is read and before the over-current limits are checked against the sensor.
void applyDerivedDefaults(const YAML::Node& root, Scenario& s);

}  // namespace packsim
