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
  // The array's power over the recording interval that ends at the sample (its mean
  // since the previous sample; 0 at the first): what went into the bus -- less than the
  // MPPT had when the pack refused the charge (full, tripped, a blocked FET) -- and
  // what the MPPT had to give. Their sums over the samples × the interval are the
  // summary's array energy and the energy the array had.
  double array_W = 0.0;
  double array_available_W = 0.0;
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

// One stage of a multi-day route (route.stages): from setting off at its start to
// standing at its end (control stops inside it count in its time), then parked there
// until the next stage sets off (docs/vehicle.md, "Stages and stops").
struct StageRecord {
  int stage = 0;                // 1-based
  double depart_s = 0.0;        // set off from the stage's start
  double time_s = 0.0;          // from setting off to its end (or the run's end)
  double distance_m = 0.0;
  double pack_Wh = 0.0;         // energy out of the pack terminals over the stage
  double array_Wh = 0.0;        // array energy taken into the bus over the stage
  bool complete = false;        // false: the stage the run ended in
  // Parked after the stage until the next one set off (or the run ended): its time, the
  // pack's energy out over it (negative: the array charged it) and the array's energy.
  double parked_s = 0.0, parked_pack_Wh = 0.0, parked_array_Wh = 0.0;
};

struct VehicleSummary {
  bool present = false;
  std::vector<LapRecord> laps;
  std::vector<StageRecord> stages;  // route.stages only
  double clock_start_hour = 0.0;    // solar time of day at t = 0 (with stages: the stage table's times)
  double distance_m = 0.0;
  double route_m = 0.0;
  double time_limit_s = 0.0;     // the route's time limit (0: none)
  double start_s = 0.0;          // the driver set off: the first tick the BMS was ready (normal),
                                 // or with stages stage 1's start (it waits at the start line till then)
  double ready_s = 0.0;          // the first tick the BMS was ready (normal)
  // Before setting off (start_s > ready_s: waiting at the start line for stage 1, the array
  // charging the pack): the pack's energy out and the array's then -- in no lap or stage.
  double prestart_pack_Wh = 0.0, prestart_array_Wh = 0.0;
  double time_s = 0.0;           // at the finish line, or the run's end
  bool finished = false;
  bool stood_still = false;      // ended standing although the driver wanted to move
  double sun_table_end_s = -1.0; // the run ended at the end of its irradiance table (-1: it did not)
  double reference_time_s = 0.0; // the reference vehicle's finishing time (0: it did not finish)
  double pack_Wh = 0.0, array_Wh = 0.0;
  // The first tick a pack limit cut the drive (controller current, fold-back, shortfall).
  bool limited = false;
  double limit_time_s = 0.0;
  double limit_distance_m = 0.0;
  int limit_lap = 0;              // 1-based
  std::string limit_detail;
  double limited_s = 0.0;         // total time a pack limit acted
  // bms.charge_full_cell_V with an array: the first time the BMS read it on the highest
  // module and the array's charge of the pack ended (-1: never).
  double array_full_s = -1.0;
};

}  // namespace packsim
