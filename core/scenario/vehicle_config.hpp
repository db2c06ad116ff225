// `load: {vehicle, route, driver, sun}`: a vehicle driven over a route in front of the
// pack instead of a current or power profile (docs/vehicle.md, docs/scenario.md).
#pragma once
#include "models/vehicle/clear_sky.hpp"
#include "models/vehicle/road_load.hpp"
#include "models/vehicle/route.hpp"
#include "models/vehicle/vehicle.hpp"

namespace packsim {

struct VehicleConfig {
  bool present = false;
  VehicleParams params;
  Route route;
  DriverParams driver;
  SolarArray array;  // area 0: no array
  // The run ends when the vehicle has stood still this long although its driver
  // wants to move (a pack that can no longer move it).
  double standstill_end_s = 60.0;
};

}  // namespace packsim
