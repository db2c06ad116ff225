// What a vehicle run reports (core/sim/vehicle_run.hpp): one record per lap, the first
// moment and place the pack limited the vehicle, and the time that cost it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace packsim {

// The vehicle's state at a recorded sample (the result file's /vehicle channels).
struct VehicleSample {
  double distance_m = 0.0;
  double speed_m_per_s = 0.0;
  double pack_request_W = 0.0;  // pack power asked for over the next tick (drive + aux - array)
  double array_W = 0.0;         // solar array power into the bus
  uint8_t limit = 0;            // DriveLimit of the last tick (models/vehicle/vehicle.hpp)
};

struct LapRecord {
  int lap = 0;                  // 1-based
  double start_s = 0.0;
  double time_s = 0.0;
  double distance_m = 0.0;
  double pack_Wh = 0.0;         // energy out of the pack terminals over the lap
  double array_Wh = 0.0;        // array energy taken into the bus
  double reference_time_s = 0.0;  // the same driver on a pack that never limits it (0: not reached)
  bool complete = false;        // false: the lap the run ended in
};

struct VehicleSummary {
  bool present = false;
  std::vector<LapRecord> laps;
  double distance_m = 0.0;
  double route_m = 0.0;
  double time_limit_s = 0.0;     // the route's time limit (0: none)
  double start_s = 0.0;          // the driver set off: the first tick the BMS was ready (normal)
  double time_s = 0.0;           // at the finish line, or the run's end
  bool finished = false;
  bool stood_still = false;      // ended standing although the driver wanted to move
  double reference_time_s = 0.0; // the reference vehicle's finishing time (0: it did not finish)
  double pack_Wh = 0.0, array_Wh = 0.0;
  // The first tick a pack limit cut the drive (controller current, fold-back, shortfall).
  bool limited = false;
  double limit_time_s = 0.0;
  double limit_distance_m = 0.0;
  int limit_lap = 0;              // 1-based
  std::string limit_detail;
  double limited_s = 0.0;         // total time a pack limit acted
};

}  // namespace packsim
