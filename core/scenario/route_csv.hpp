// A route from a CSV table (load.route.csv; docs/vehicle.md, "A route from a CSV"): a
// header row, then one row per point along the road. Columns, by name:
//
//   distance_km or distance_m   where the point is along the road (what the vehicle
//                               drives, as segments' length_m); the first 0, then
//                               strictly increasing
//   grade_percent or elevation_m  the grade (rise over run) from this point to the next,
//                               or the elevations: the road between two points rises
//                               Δh over Δd of road, sin θ = Δh/Δd
//   speed_kmh                   the target speed from this point to the next
//   headwind_kmh                optional: the wind against the direction of travel from
//                               this point on (negative: a tailwind); or instead
//   wind_kmh, wind_from_deg, heading_deg   the wind's speed, the compass direction it
//                               blows from and the direction of travel: headwind =
//                               wind · cos(wind_from − heading)
//
// Each row but the last starts a segment that ends at the next row; the last row is
// the route's end (only its distance, and its elevation, are used). Errors name the
// file, the line, the column and the allowed range.
#pragma once
#include <string>
#include <vector>

#include "models/vehicle/route.hpp"

namespace packsim {

std::vector<RouteSegment> readRouteCsv(const std::string& path);

}  // namespace packsim
