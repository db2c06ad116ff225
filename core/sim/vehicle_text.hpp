// The vehicle's lines of the run summary: the route and its time, the lap table, the
// first moment and place the pack limited the vehicle, the time that cost, the range.
#pragma once
#include <string>

#include "core/sim/vehicle_summary.hpp"

namespace packsim {

std::string vehicleSummaryLines(const VehicleSummary& v);

}  // namespace packsim
