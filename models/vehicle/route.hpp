// A route: a circuit of distance-based segments, each with its grade and the speed the
// driver aims for on it, driven for a number of laps, with the places the vehicle
// stops on the way: control stops of a set duration and the ends of a multi-day race's
// stages, where it waits for the next stage's start time (docs/vehicle.md).
#pragma once
#include <vector>

namespace packsim {

struct RouteSegment {
  double length_m = 0.0;
  double grade = 0.0;           // rise over run (0.05 = 5 %)
  double speed_m_per_s = 0.0;   // target speed (the speed limit the driver keeps to)
  double headwind_m_per_s = 0.0;  // the wind against the direction of travel (negative: tailwind)
};

// A place the vehicle stops: it brakes to a standstill there and stays parked for at
// least duration_s and until not_before_s (run time; a stage's start time).
struct RouteStop {
  double at_m = 0.0;
  double duration_s = 0.0;
  double not_before_s = 0.0;
  int stage_end = -1;  // the stage (1-based) that ends here, 0: the start line before stage 1; -1: a control stop
};

struct Route {
  std::vector<RouteSegment> segments;
  // Ascending in at_m. With stages: first a stop at 0 m until stage 1's start time, then
  // the control stops and the stage ends (the last stage ends at the finish line: no stop).
  std::vector<RouteStop> stops;
  int stages = 0;  // 0: one run from start to finish, no stage table
  int laps = 1;
  double time_limit_s = 0.0;  // the race's time limit for the route (0: none)

  double lap_m() const;
  double total_m() const { return lap_m() * laps; }
  // The segment at distance s from the start (laps repeat; past the end: the last one).
  int segmentAt(double s_m) const;
  // Completed laps at distance s (0 .. laps).
  int lapAt(double s_m) const;
  // The fastest speed at s from which braking at b still reaches every later
  // segment's target speed at its start (within this lap and the next), and at most
  // the segment's own target: min(v_k, min_j sqrt(v_j² + 2·b·(s_j - s))).
  double targetSpeed_m_per_s(double s_m, double brake_m_per_s2) const;
};

}  // namespace packsim
