// The vehicle's lines of the run summary: the route and its time, the lap table, the
// first moment and place the pack limited the vehicle, the time that cost, the range.
#pragma once
#include <string>
#include <vector>

#include "core/sim/vehicle_summary.hpp"

namespace packsim {

class LineWriter;

// A table of lines as the summary's (summary_text.hpp SummaryLine), for a vehicle run.
struct VehicleLine {
  const char* label;
  const char* fields;  // the /summary figures it prints: summaryFields() names, space-separated
  void (*write)(LineWriter& w, const VehicleSummary& v);
};
const std::vector<VehicleLine>& vehicleLines();

// Every row's lines (none without a vehicle).
void writeVehicleLines(LineWriter& w, const VehicleSummary& v);

}  // namespace packsim
