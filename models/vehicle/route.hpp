// A route: a circuit of distance-based segments, each with its grade and the speed the
// driver aims for on it, driven for a number of laps (docs/vehicle.md).
#pragma once
#include <vector>

namespace packsim {

struct RouteSegment {
  double length_m = 0.0;
  double grade = 0.0;           // rise over run (0.05 = 5 %)
  double speed_m_per_s = 0.0;   // target speed (the speed limit the driver keeps to)
};

struct Route {
  std::vector<RouteSegment> segments;
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
